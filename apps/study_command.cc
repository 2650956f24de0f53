// `demfem study FILE.prm` (docs/architecture.md, "Speed-versus-accuracy
// study"): runs the embedded tunnel (no VTK) for every combination of the swept
// settings (region radius, grain resolution a/d, coupling variant, scheme,
// subcycles, time-step safety, relaxation, stiffness contrast, seed) and writes
// study.csv (one row per run), study_pareto.svg (wall time versus error, Pareto
// front marked) and summary.json (stability limits per scheme setting, overall
// and per scheme; the right-sized region radius). Elastic mode: unbreakable
// bonds, error against Kirsch. Breakable mode: a full-DEM reference per
// resolution and seed (coupling/full_dem_reference.h), each run's damage-zone
// depth and crack counts against it, study_speedup.csv and study.md. A run that
// diverges is a result (unstable, with the engine's diagnosis), not an error; a
// combination the tunnel run refuses is an 'invalid' row. Exit codes: 0 done, 1
// bad input or error.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/output_dir.h"
#include "apps/prm_cli.h"
#include "apps/study.h"
#include "common/atomic_file.h"
#include "common/json_number.h"
#include "dem/engine/types.h"
#include "dem/io/vtk_output.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

namespace demfem::apps
{
  namespace
  {
    using namespace dealii;

    const char *usage =
        "usage: demfem study FILE.prm [--set \"Section/key=value\"]... "
        "[--print-parameters] [--help]\n"
        "\n"
        "Speed versus accuracy of the coupled tunnel model: runs the embedded\n"
        "tunnel for every combination of the values listed in the Study subsection\n"
        "(region radius factors x tunnel radius, grain resolutions a/d, coupling\n"
        "variants, schemes, subcycles, time-step safety factors, relaxation factors,\n"
        "stiffness contrasts, packing seeds); the other keys are those of `demfem\n"
        "tunnel`. Elastic mode (default): unbreakable bonds, error against Kirsch\n"
        "(2D, and the 3D slab and section: Problem/dimension = 3).\n"
        "Study/breakable = true: breakable bonds, damage-zone depth and crack counts\n"
        "against a full-DEM reference (radius Study/reference radius factor x a,\n"
        "in-situ stress held by a servo-controlled membrane; 3D: the plane-strain\n"
        "slab of the region's thickness), speed-up table.\n"
        "'DEM region/radius = auto' sizes the region from a Kirsch pre-analysis\n"
        "(sigma1 - sigma3 >= Study/damage threshold x UCS, plus Study/margin grains).\n"
        "Writes study.csv, study_pareto.svg, summary.json (stability map per scheme),\n"
        "in breakable mode study_speedup.csv, study.md and (two seeds or more)\n"
        "study_seeds.svg, and one directory per run\n"
        "into Problem/output directory.\n";

    std::string num(double v)
    {
      std::ostringstream s;
      s << std::setprecision(8) << (std::isfinite(v) ? v : 0.0);
      return s.str();
    }

    // Stability map. The scheme settings swept: time-step safety, subcycles,
    // relaxation factor and stiffness contrast. For one of them, the largest
    // value whose runs were all stable and the smallest value with an unstable
    // run, among the runs whose other settings are at their most conservative
    // swept value (smallest safety, subcycles and relaxation; contrast closest
    // to 1), so that a too-large safety does not mark every subcycling ratio
    // unstable.
    using Getter = double (*)(const study::Row &);
    const std::vector<std::pair<std::string, Getter>> &axes()
    {
      static const std::vector<std::pair<std::string, Getter>> a = {
          {"timestep_safety", [](const study::Row &r) { return r.safety; }},
          {"subcycles", [](const study::Row &r) { return double(r.subcycles); }},
          {"relaxation", [](const study::Row &r) { return r.relaxation; }},
          {"stiffness_contrast", [](const study::Row &r) { return r.contrast; }}};
      return a;
    }

    // Whether an axis is a setting of the row's scheme: the relaxation is
    // read by the quasi-static scheme only (study::uses_relaxation), so the
    // other schemes' rows neither map it nor are filtered by it.
    bool applies(const study::Row &r, std::size_t axis)
    {
      return axis != 2 || study::uses_relaxation(r.scheme);
    }

    // Sub-cycling lengthens the explicit and condensed schemes' windows, but
    // it is what gives the quasi-static iteration's DEM time to respond
    // within a window (k <= 50 diverged, docs/tunnel.md): for that scheme a
    // larger k is the conservative side.
    bool larger_is_safer(const study::Row &r, std::size_t axis)
    {
      return axis == 1 && r.scheme == "quasi-static";
    }

    // The most conservative swept value of an axis among the rows of one
    // scheme.
    double conservative(const std::vector<const study::Row *> &rows, std::size_t axis,
                        const std::string &scheme)
    {
      double best = 0;
      bool   set  = false;
      for (const auto *r : rows)
        {
          if (r->scheme != scheme || !applies(*r, axis))
            continue;
          const double v      = axes()[axis].second(*r);
          const bool   better = axis == 3
                                    ? std::abs(std::log(v)) < std::abs(std::log(best))
                                    : (larger_is_safer(*r, axis) ? v > best : v < best);
          if (!set || better)
            best = v, set = true;
        }
      return best;
    }

    // Writes the map of `rows`. An axis that none of their schemes has (the
    // relaxation of explicit or condensed runs) gets no key rather than a
    // limit it never tested; the quasi-static subcycles, stable from some k
    // upwards, get `_smallest_stable` / `_largest_unstable` keys instead.
    void limits(nlohmann::ordered_json &o, const std::string &prefix,
                const std::vector<const study::Row *> &rows, const std::string &label)
    {
      for (std::size_t ax = 0; ax < axes().size(); ++ax)
        for (const bool up : {false, true})
          {
            std::map<double, bool> all_stable;
            bool                   any = false;
            for (const auto *r : rows)
              {
                if (!applies(*r, ax) || larger_is_safer(*r, ax) != up)
                  continue;
                any = true;
                if (r->status == "invalid")
                  continue;
                bool others = true;
                for (std::size_t b = 0; b < axes().size(); ++b)
                  others = others &&
                           (b == ax || !applies(*r, b) ||
                            axes()[b].second(*r) == conservative(rows, b, r->scheme));
                if (!others)
                  continue;
                const double v  = axes()[ax].second(*r);
                const auto   it = all_stable.find(v);
                const bool   ok = r->status == "stable";
                all_stable[v]   = it == all_stable.end() ? ok : it->second && ok;
              }
            if (!any)
              continue;
            // Walk from the conservative end to the first unstable value.
            std::vector<std::pair<double, bool>> walk(all_stable.begin(),
                                                      all_stable.end());
            if (up)
              std::reverse(walk.begin(), walk.end());
            std::optional<double> best, first_bad;
            for (const auto &[v, ok] : walk)
              {
                if (!ok)
                  {
                    first_bad = v;
                    break;
                  }
                best = v;
              }
            const std::string name   = prefix + axes()[ax].first;
            const std::string stable = up ? "smallest stable" : "largest stable";
            const std::string bad    = up ? "largest unstable" : "smallest unstable";
            auto              key    = [](std::string t) {
              std::replace(t.begin(), t.end(), ' ', '_');
              return "_" + t;
            };
            o[name + key(stable)] = best ? json_number(*best) : nullptr;
            o[name + key(bad)]    = first_bad ? json_number(*first_bad) : nullptr;
            if (all_stable.size() > 1 || first_bad)
              std::cout << "demfem study: " << label << axes()[ax].first << ": " << stable
                        << " " << (best ? num(*best) : std::string("none")) << ", " << bad
                        << " "
                        << (first_bad ? num(*first_bad)
                                      : std::string("none (not reached)"))
                        << "\n";
          }
    }

    /// The `demfem tunnel` command that repeats run `p` of the sweep (from
    /// the directory the study ran in): the study's file and --set
    /// overrides, then the run's swept values to 17 digits, so that the
    /// region packs the same grains (a rounded diameter packs another
    /// realization). Empty, with the reason in `why`, when keys cannot say
    /// it: a stiffness contrast on a material file's continuum (the file
    /// sets E).
    std::string repeat_command(const coupling::TunnelParams &p, double contrast,
                               std::string &why)
    {
      if (p.region.material && contrast != 1)
        {
          why = "the continuum's E is the material file's x the contrast; no key "
                "gives it with a material file";
          return {};
        }
      std::vector<std::string> sets;
      for (const auto &o : command_line().overrides)
        if (o.rfind("Problem/output directory=", 0) != 0)
          sets.push_back(o);
      auto set = [&](const std::string &key, const std::string &value) {
        sets.push_back(key + "=" + value);
      };
      auto g17 = [](double v) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", v);
        return std::string(buf);
      };
      set("DEM region/radius", g17(p.region.radius));
      if (p.region.material) // the file's sizes scaled to this mean diameter
        set("DEM region/grain diameter", g17(p.region.mean_diameter()));
      else
        {
          set("DEM region/grain diameter", "");
          set("DEM region/grain diameter min", g17(p.region.d_lo));
          set("DEM region/grain diameter max", g17(p.region.d_hi));
        }
      set("DEM region/seed", std::to_string(p.region.seed));
      set("DEM region/breakable", p.region.breakable ? "true" : "false");
      set("Coupling/variant", p.coupling.variant);
      set("Coupling/scheme", p.coupling.scheme);
      set("Coupling/subcycles", std::to_string(p.coupling.subcycles));
      set("Coupling/timestep safety", g17(p.coupling.safety));
      set("Coupling/relaxation", g17(p.coupling.relaxation));
      if (!p.region.material)
        set("Continuum/young modulus", g17(p.continuum.young_modulus));
      set("Problem/output directory", p.output_directory + "/repeat");
      std::vector<std::string> args = {"demfem", "tunnel"};
      if (command_line().defaults)
        args.push_back("--defaults");
      if (!command_line().file.empty())
        args.push_back(command_line().file);
      for (const auto &o : sets)
        args.insert(args.end(), {"--set", o});
      return shell_quoted(args);
    }

    // One run of the sweep: the tunnel with the swept settings applied. A
    // combination the tunnel run rejects (e.g. a region too small for the
    // grains, or a variant/scheme not implemented) is an 'invalid' row, a
    // diverged run an 'unstable' row: neither stops the sweep.
    study::Row run_one(const coupling::TunnelParams &base, double a,
                       const std::optional<double> &f, double r,
                       const std::string &variant, const std::string &scheme,
                       unsigned int k, double s, double rx, double c, std::uint64_t seed,
                       std::map<double, study::AutoRadius> &autos,
                       const coupling::RegionParams &region, double kirsch,
                       const study::Settings               &st,
                       const std::vector<study::Reference> &refs, int reference,
                       const std::string &out, int index)
    {
      study::Row row;
      row.index                 = index;
      coupling::TunnelParams p  = base;
      row.region_auto           = !f;
      p.region                  = region;
      p.region.radius           = f ? *f * a : autos[r].radius;
      p.coupling.variant        = variant;
      p.coupling.scheme         = scheme;
      p.coupling.subcycles      = k;
      p.coupling.safety         = s;
      p.coupling.relaxation     = rx;
      p.continuum.young_modulus = c * base.continuum.young_modulus;
      row.seed                  = seed;
      std::ostringstream dir;
      dir << out << "/run_" << std::setw(3) << std::setfill('0') << row.index;
      p.output_directory = dir.str();
      row.region_radius  = p.region.radius;
      row.region_factor  = p.region.radius / a;
      row.resolution     = r;
      row.grain_d        = a / r;
      row.subcycles      = k;
      row.safety         = s;
      row.variant        = variant;
      row.scheme         = scheme;
      row.relaxation     = rx;
      row.contrast       = c;
      row.kirsch         = kirsch;
      row.breakable      = st.breakable;
      row.reference      = reference;
      std::ostringstream log;
      try
        {
          p.validate("parameter file");
          row.result     = coupling::run_tunnel(p, log);
          row.status     = row.result.diverged ? "unstable" : "stable";
          row.diagnosis  = row.result.diagnosis;
          const double u = row.result.wall_convergence_mean;
          if (!row.result.diverged && !std::isfinite(u))
            row.status = "unstable", row.diagnosis = "non-finite wall convergence";
          // The run's own outcome checks (coupling/tunnel_result.h): a run
          // whose phases ended at the step limit has a meaningless error
          // (measured: k = 20, a/d = 6 ended at ratio 0.55 and 55 % short of
          // Kirsch). A region stress off sigma0 is noted, not excluded: with
          // a stiffness contrast it is the effect the sweep measures (a soft
          // region in a stiff continuum carries less than sigma0).
          const auto &res  = row.result;
          row.final_ratio  = res.phases.empty() ? -1 : res.phases.back().unbalanced_ratio;
          row.equilibrated = true;
          for (const auto &[st, what] : res.problems)
            {
              const bool unusable = st == coupling::RunStatus::not_equilibrated ||
                                    st == coupling::RunStatus::time_not_advancing;
              if (row.status == "stable" &&
                  (row.diagnosis.empty() || (unusable && row.equilibrated)))
                row.diagnosis = coupling::status_name(st) + ": " + what +
                                (unusable ? " (error not meaningful)" : "");
              if (unusable)
                row.equilibrated = false;
            }
          if (row.status != "stable")
            row.error = 0;
          else if (!st.breakable)
            {
              row.error            = (u - kirsch) / kirsch;
              row.kirsch_at_grains = study::kirsch_convergence_at(
                  base.sigma0, a, base.continuum.young_modulus,
                  base.continuum.poisson_ratio, res.wall_points);
              row.error_at_grains = (u - row.kirsch_at_grains) / row.kirsch_at_grains;
            }
          else
            {
              // Agreement with the full-DEM reference on the damage-zone
              // depth (relative) and the excavation crack count.
              row.region_too_small  = res.region_too_small;
              row.cracks_excavation = res.cracks_total - res.cracks_before_excavation;
              row.error             = std::nan("");
              if (reference >= 0 && refs[reference].usable())
                {
                  const auto &ref     = refs[reference];
                  row.reference_depth = ref.result.damage_zone_depth;
                  row.error = (row.result.damage_zone_depth - row.reference_depth) /
                              row.reference_depth;
                  row.cracks_diff =
                      ref.cracks_excavation() > 0
                          ? (double(row.cracks_excavation) - ref.cracks_excavation()) /
                                ref.cracks_excavation()
                          : std::nan("");
                  row.reference_area = ref.result.damage.damaged_area;
                  row.area_diff =
                      row.reference_area > 0
                          ? (row.result.damage.damaged_area - row.reference_area) /
                                row.reference_area
                          : std::nan("");
                  // The same damage is the same depth and the same damaged
                  // area (a 3D section with 8 cracks had the reference's
                  // depth within 5 % and 4 % of its area). A run whose cracks
                  // reached the coupling boundary does not agree whatever its
                  // numbers: its damage zone was cut by the region (the
                  // continuum cannot crack).
                  row.agrees = std::abs(row.error) <= st.agreement_tolerance &&
                               !(std::abs(row.area_diff) > st.agreement_tolerance) &&
                               !row.region_too_small;
                }
              else if (row.diagnosis.empty())
                row.diagnosis = "no usable full-DEM reference (failed or no damage)";
              if (row.region_too_small && row.diagnosis.empty())
                row.diagnosis = "region_too_small: the damage zone (cracks connected "
                                "to the wall) within two grain diameters of the "
                                "coupling boundary";
            }
        }
      catch (const std::exception &e)
        {
          row.status    = "invalid";
          row.diagnosis = exception_text(e);
        }
      if (std::filesystem::is_directory(p.output_directory))
        {
          write_file_atomically(p.output_directory + "/log.txt", log.str());
          std::string why;
          const auto  cmd = repeat_command(p, c, why);
          write_file_atomically(p.output_directory + "/command.txt",
                                cmd.empty()
                                    ? "# not repeatable by demfem tunnel: " + why + "\n"
                                    : cmd + "\n");
        }
      std::cout << "run " << row.index << ": b/a " << row.region_factor << ", a/d " << r
                << ", " << variant << ", " << scheme << ", k " << k << ", safety " << s
                << ", relaxation " << rx << ", contrast " << c << ", seed " << seed
                << ": " << row.status;
      if (row.status == "stable" && row.equilibrated)
        {
          std::cout << ", " << row.result.n_particles << " grains, " << row.result.steps
                    << " steps, " << row.result.wall_time_s << " s, ";
          if (st.breakable)
            std::cout << "damage-zone depth " << row.result.damage_zone_depth << " m, "
                      << row.cracks_excavation << " excavation cracks"
                      << (row.region_too_small ? ", region_too_small" : "");
          if (std::isfinite(row.error))
            std::cout << (st.breakable ? ", depth difference " : "error ")
                      << 100 * row.error << " %";
        }
      else
        std::cout << " (" << row.diagnosis << ")";
      std::cout << std::endl;
      return row;
    }
  } // namespace

  int run_study(int argc, char **argv)
  {
    Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
    std::optional<RunDirectory>      run_dir;
    try
      {
        ParameterHandler prm;
        declare_tunnel_parameters(prm);
        study::declare_study_parameters(prm);
        std::string file;
        if (answered(read_parameters(argc, argv, prm, usage, file), prm, usage,
                     &std::cout))
          return 0;
        coupling::TunnelParams base = read_tunnel_settings(prm);
        prm.enter_subsection("DEM region");
        const std::string material = resolve_input_file(prm.get("material file"));
        prm.leave_subsection();
        const study::Settings st = study::read_study_settings(prm, material);
        // Breakable 3D: the full-DEM reference is the plane-strain slab of
        // the embedded region's thickness, r <= R, in a cylindrical membrane
        // (coupling/full_dem_reference.h); the embedded slab is plane
        // strain through the same walls, the section's far field through
        // the continuum's rollers.
        // Elastic mode: unbreakable bonds, compared with Kirsch. Breakable
        // mode: compared with the full-DEM reference.
        base.region.breakable = st.breakable;
        base.write_vtk        = false;
        const double a        = base.tunnel_radius;
        AssertThrow(a > 0, ExcMessage("Tunnel/radius must be > 0"));

        // The sweep axes; an empty list keeps the tunnel value.
        std::vector<std::optional<double>> factors = st.radius_factors;
        if (factors.empty())
          factors.push_back(base.region.radius < 0
                                ? std::optional<double>()
                                : std::optional<double>(base.region.radius / a));
        auto or_base = [](auto list, auto value) {
          if (list.empty())
            list.push_back(value);
          return list;
        };
        const std::vector<double> res =
            or_base(st.resolutions, a / base.region.mean_diameter());
        const auto ks       = or_base(st.subcycles, base.coupling.subcycles);
        const auto seeds    = or_base(st.seeds, base.region.seed);
        const auto ss       = or_base(st.safeties, base.coupling.safety);
        const auto variants = or_base(st.variants, base.coupling.variant);
        const auto schemes  = or_base(st.schemes, base.coupling.scheme);
        const auto relax    = or_base(st.relaxations, base.coupling.relaxation);
        const auto contrast = or_base(st.stiffness_contrasts, 1.0);

        // Kirsch with the material's constants (the continuum's as given):
        // a stiffness contrast != 1 is a mismatch that shows as error.
        const double kirsch = study::kirsch_mean_convergence(
            base.sigma0, a, base.continuum.young_modulus, base.continuum.poisson_ratio);
        if (!st.breakable)
          std::cout << "demfem study: Kirsch mean wall convergence " << kirsch
                    << " m (plane strain, E = " << base.continuum.young_modulus
                    << " Pa, nu = " << base.continuum.poisson_ratio << ")\n";

        // Right-sizing (per resolution: the margin is in grain diameters).
        bool                                any_auto = false;
        std::map<double, study::AutoRadius> autos;
        for (const auto &f : factors)
          any_auto = any_auto || !f;
        if (any_auto)
          for (const double r : res)
            {
              autos[r] = study::auto_region_radius(
                  base.sigma0, a, st.ucs, st.damage_fraction, st.margin_grains, a / r);
              std::cout << "demfem study: DEM region/radius = auto (a/d = " << r
                        << "): damage zone sigma1 - sigma3 >= " << autos[r].threshold
                        << " Pa reaches r = " << autos[r].damage_radius
                        << " m; region radius " << autos[r].radius << " m ("
                        << st.margin_grains << " grains margin)\n";
            }

        const std::string out = base.output_directory;
        claim_output_directory(run_dir, out, prm);

        // The region of a resolution (grain sizes scaled, d_max/d_min kept).
        auto region_at = [&](double r, std::uint64_t seed) {
          coupling::RegionParams g     = base.region;
          const double           scale = (a / r) / base.region.mean_diameter();
          g.scale_grains(scale); // with a material: its microstructure too
          // 3D: the slab (or section) keeps its thickness in grain
          // diameters (DEM region/slab thickness).
          g.slab_thickness = base.region.slab_thickness * scale;
          g.seed           = seed;
          return g;
        };

        // Breakable mode: one full-DEM reference per resolution and seed,
        // run before the embedded runs (its wall time is the speed-up base).
        std::vector<study::Reference> refs;
        auto                          reference_of = [&](double r, std::uint64_t seed) {
          for (std::size_t i = 0; i < refs.size(); ++i)
            if (refs[i].resolution == r && refs[i].seed == seed)
              return int(i);
          return -1;
        };
        if (st.breakable)
          for (const double r : res)
            for (const std::uint64_t seed : seeds)
              {
                study::Reference f;
                f.resolution = r;
                f.seed       = seed;
                std::ostringstream dir;
                dir << out << "/reference_" << std::setw(2) << std::setfill('0')
                    << refs.size();
                f.directory = dir.str();
                coupling::FullDemReferenceParams q;
                q.dimension         = base.dimension;
                q.output_directory  = f.directory;
                q.tunnel_radius     = a;
                q.sigma0            = base.sigma0;
                q.stages            = base.stages;
                q.region            = region_at(r, seed);
                q.region.radius     = st.reference_radius_factor * a;
                q.min_radius_factor = 8;
                // the most conservative swept safety, at most 0.8
                q.safety = std::min(0.8, *std::min_element(ss.begin(), ss.end()));
                q.ratio_tolerance       = base.ratio_tolerance;
                q.ramp_crossing_times   = base.ramp_crossing_times;
                q.damage_link_diameters = base.damage_link_diameters;
                q.crack_initiation      = base.crack_initiation;
                q.poisson_ratio         = base.continuum.poisson_ratio;
                q.phase_step_limit      = base.phase_step_limit;
                q.history_interval      = base.history_interval;
                q.servo.tolerance       = st.servo_tolerance;
                std::cout << "demfem study: full-DEM reference (R = " << q.region.radius
                          << " m, a/d = " << r << ", seed " << seed << ") ..."
                          << std::endl;
                std::ostringstream log;
                try
                  {
                    f.result    = coupling::run_full_dem_reference(q, log);
                    f.status    = coupling::status_name(f.result.status);
                    f.diagnosis = f.result.diagnosis;
                  }
                catch (const std::exception &e)
                  {
                    f.status    = "invalid";
                    f.diagnosis = exception_text(e);
                  }
                if (std::filesystem::is_directory(f.directory))
                  write_file_atomically(f.directory + "/log.txt", log.str());
                std::cout << "reference " << refs.size() << ": " << f.status;
                if (f.status != "invalid")
                  std::cout << ", " << f.result.n_particles << " grains, "
                            << f.result.steps << " steps, " << f.result.wall_time_s
                            << " s, damage-zone depth " << f.result.damage_zone_depth
                            << " m, " << f.cracks_excavation()
                            << " excavation cracks, servo error in situ "
                            << f.result.servo_error_insitu;
                if (!f.diagnosis.empty())
                  std::cout << " (" << f.diagnosis << ")";
                std::cout << std::endl;
                refs.push_back(f);
              }

        std::vector<study::Row> rows;
        for (const auto &f : factors)
          for (const double r : res)
            for (const auto &variant : variants)
              for (const auto &scheme : schemes)
                for (const unsigned int k : ks)
                  for (const double s : ss)
                    for (const double rx : relax)
                      for (const double c : contrast)
                        for (const std::uint64_t seed : seeds)
                          // a scheme without relaxation would repeat the same
                          // run for every relaxation value
                          if (study::uses_relaxation(scheme) || rx == relax.front())
                            rows.push_back(
                                run_one(base, a, f, r, variant, scheme, k, s, rx, c, seed,
                                        autos, region_at(r, seed), kirsch, st, refs,
                                        reference_of(r, seed), out, int(rows.size())));

        study::mark_pareto(rows);
        study::write_csv(out + "/study.csv", rows);
        double ref_time = 0;
        for (const auto &f : refs)
          ref_time = std::max(ref_time, f.result.wall_time_s);
        study::write_chart(out + "/study_pareto.svg", rows, st.breakable, ref_time);
        study::RegionAnswer answer;
        std::size_t         n_speedup = 0;
        if (st.breakable)
          {
            answer = study::region_answer(rows, refs, st.agreement_tolerance);
            n_speedup =
                study::write_speedup(out + "/study_speedup.csv", out + "/study.md", rows,
                                     refs, st.agreement_tolerance, answer);
            const auto groups = study::seed_groups(rows, refs);
            if (!groups.empty())
              study::write_seed_chart(out + "/study_seeds.svg", groups);
          }

        nlohmann::ordered_json j; // summary.json
        std::size_t            n_stable = 0, n_unstable = 0;
        for (const auto &r : rows)
          {
            n_stable += r.status == "stable";
            n_unstable += r.status == "unstable";
          }
        j["mode"]      = st.breakable ? "breakable" : "elastic";
        j["dimension"] = base.dimension;
        if (base.dimension == 3)
          j["embedding"] = base.continuum.axial_extension > 0 ? "section" : "slab";
        j["runs"]     = rows.size();
        j["stable"]   = n_stable;
        j["unstable"] = n_unstable;
        j["invalid"]  = rows.size() - n_stable - n_unstable;
        j["stable_not_equilibrated"] =
            std::count_if(rows.begin(), rows.end(), [](const study::Row &r) {
              return r.status == "stable" && !r.equilibrated;
            });
        if (!st.breakable)
          j["kirsch_convergence_m"] = json_number(kirsch);
        // Stability map: over all runs (keys as before), then per scheme.
        std::vector<const study::Row *> all;
        for (const auto &r : rows)
          all.push_back(&r);
        limits(j, "", all, "");
        for (const auto &scheme : schemes)
          {
            std::vector<const study::Row *> sub;
            for (const auto &r : rows)
              if (r.scheme == scheme)
                sub.push_back(&r);
            std::string key = scheme;
            std::replace(key.begin(), key.end(), '-', '_');
            limits(j, "stability_" + key + "_", sub, scheme + ": ");
          }
        if (any_auto)
          {
            const auto &ar                = autos.begin()->second;
            j["auto_damage_threshold_Pa"] = json_number(ar.threshold);
            j["auto_ucs_Pa"]              = json_number(st.ucs);
            j["auto_damage_radius_m"]     = json_number(ar.damage_radius);
            j["auto_margin_grains"]       = json_number(st.margin_grains);
            j["auto_region_radius_m"]     = json_number(ar.radius);
            j["auto_a_over_d"]            = json_number(autos.begin()->first);
          }
        if (st.breakable)
          {
            j["agreement_tolerance"]     = json_number(st.agreement_tolerance);
            j["reference_radius_factor"] = json_number(st.reference_radius_factor);
            auto references              = nlohmann::ordered_json::array();
            for (const auto &f : refs)
              references.push_back(
                  {{"directory", f.directory},
                   {"status", f.status},
                   {"a_over_d", json_number(f.resolution)},
                   {"seed", f.seed},
                   {"reference_particles", f.result.n_particles},
                   {"reference_steps", f.result.steps},
                   {"reference_wall_time_s", json_number(f.result.wall_time_s)},
                   {"reference_damage_zone_depth",
                    json_number(f.result.damage_zone_depth)},
                   {"reference_cracks_excavation", f.cracks_excavation()},
                   {"reference_cracks_tensile", f.result.cracks_tensile},
                   {"reference_cracks_shear", f.result.cracks_shear},
                   {"reference_wall_convergence",
                    json_number(f.result.wall_convergence_mean)},
                   {"reference_servo_error_insitu",
                    json_number(f.result.servo_error_insitu)}});
            j["references"]   = references;
            j["speedup_rows"] = n_speedup;
            j["region_factor_smallest_agreeing"] =
                answer.smallest_agreeing < 0 ? nullptr
                                             : json_number(answer.smallest_agreeing);
            j["region_factor_largest_disagreeing"] =
                answer.largest_disagreeing < 0 ? nullptr
                                               : json_number(answer.largest_disagreeing);
            j["region_factor_rule"] = answer.rule;
          }
        auto pareto = nlohmann::ordered_json::array();
        for (const auto &r : rows)
          if (r.pareto)
            pareto.push_back(r.index);
        j["pareto_runs"] = pareto;
        write_file_atomically(out + "/summary.json", j.dump(2) + "\n");
        std::cout << "demfem study: " << rows.size() << " runs (" << n_stable
                  << " stable, " << n_unstable << " unstable)";
        if (st.breakable)
          std::cout << ", " << n_speedup
                    << " agreeing with the reference (speed-up table " << out
                    << "/study.md)";
        std::cout << "; output in " << out << std::endl;
        if (run_dir)
          run_dir->finish("ok", 0);
        return 0;
      }
    catch (const std::exception &e)
      {
        std::cerr << "demfem study: error: " << exception_text(e) << std::endl;
        if (run_dir)
          run_dir->finish("error: " + exception_text(e), 1);
        return 1;
      }
  }
} // namespace demfem::apps
