// `demfem tunnel --probe` (apps/tunnel_probe.h; docs/tunnel.md, "The probe").
#include "apps/tunnel_probe.h"

#include "apps/lab_progress.h"
#include "apps/parallel_packings.h"

#include "common/statistics.h"

#include "dem/specimen/genesis.h"
#include "dem/specimen/lab_tests.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <tuple>

namespace demfem::apps
{
  namespace
  {
    using json = nlohmann::json;

    double number(const json &j, const char *key)
    {
      const auto it = j.find(key);
      return it != j.end() && it->is_number() ? it->get<double>() : NAN;
    }

    /// What the material file says: the measured properties, the lab
    /// specimen's grain scale and vessel, and the test settings.
    struct Reference
    {
      double E = NAN, nu = NAN, ucs = NAN, bts = NAN;
      /// The lab specimen's packing (vessel-based and in the measurement
      /// regions): reported beside the probe's, not judged.
      double porosity = NAN, measurement_porosity = NAN;
      /// The file's seed scatter of UCS and BTS and the number of packings
      /// that measured each (`Problem/seeds`; one packing: no scatter, NaN).
      double             ucs_sd = NAN, bts_sd = NAN;
      std::size_t        ucs_packings = 1, bts_packings = 1;
      double             diameter_multiplier = NAN;
      dem::VesselParams  vessel;
      dem::LabTestParams lab;
      bool               lab_recorded = false; ///< the file has "lab_tests"
    };

    Reference read_reference(const std::string &file)
    {
      Reference     r;
      std::ifstream in(file);
      const json    j        = json::parse(in, nullptr, true, true);
      r.E                    = number(j, "E");
      r.nu                   = number(j, "nu");
      r.ucs                  = number(j, "ucs");
      r.bts                  = number(j, "bts");
      r.porosity             = number(j, "porosity");
      r.measurement_porosity = number(j, "measurement_porosity");
      // Each strength's scatter over the packings that measured it (a
      // Brazilian disk that did not split has a null BTS).
      const auto sc = j.find("seed_scatter");
      const auto sv = j.find("seed_values");
      if (sc != j.end() && sc->is_object() && sv != j.end() && sv->is_object())
        for (auto [key, sd, n] : {std::tuple{"ucs", &r.ucs_sd, &r.ucs_packings},
                                  std::tuple{"bts", &r.bts_sd, &r.bts_packings}})
          if (const auto v = sv->find(key); v != sv->end() && v->is_array())
            {
              std::size_t measured = 0;
              for (const auto &x : *v)
                measured += x.is_number();
              if (measured > 1)
                *sd = number(*sc, key), *n = measured;
            }
      // The probe reads E and nu in the file's stress window (below).
      if (!(r.ucs > 0))
        throw dem::InputError("--probe: material file '" + file +
                              "': \"ucs\" is missing or not positive; the probe reads E "
                              "and nu between fit_window_low and fit_window_high x ucs");
      const auto &mp        = j.at("microparameters");
      r.diameter_multiplier = number(mp, "diameter_multiplier");
      if (const auto it = mp.find("vessel_shape"); it != mp.end() && it->is_string())
        r.vessel.shape = it->get<std::string>();
      r.vessel.H = number(mp, "vessel_H_m");
      r.vessel.W = number(mp, "vessel_W_m");
      if (const double D = number(mp, "vessel_D_m"); std::isfinite(D))
        r.vessel.D = D;
      if (const double e = number(mp, "vessel_wall_emod_Pa"); std::isfinite(e))
        r.vessel.emod = e;
      // The calibration's test settings (calibrate writes them since the
      // probe exists); older files: the fit window from its description.
      auto &lab = r.lab;
      if (const auto it = j.find("lab_tests"); it != j.end() && it->is_object())
        {
          r.lab_recorded = true;
          auto set       = [&](const char *key, auto &field) {
            if (const double v = number(*it, key); std::isfinite(v))
              field = static_cast<std::decay_t<decltype(field)>>(v);
          };
          set("strain_rate_per_s", lab.strain_rate);
          set("fit_window_low", lab.fit_lo);
          set("fit_window_high", lab.fit_hi);
          set("load_fraction", lab.load_fraction);
          set("strain_limit", lab.strain_limit);
          set("step_limit", lab.step_limit);
          set("history_interval", lab.history_interval);
          set("seating_ratio_limit", lab.ratio_limit);
          set("seating_step_limit", lab.seat_step_limit);
          set("platen_friction", lab.platen_friction);
          set("split_fraction", lab.split_fraction);
          set("time_step_safety", lab.timestep_safety);        // 0 (absent): the genesis'
          set("brazilian_diameter_m", lab.brazilian_diameter); // 0 (absent): carved
          set("brazilian_thickness_m", lab.brazilian_thickness);
          set("brazilian_flat_angle_deg", lab.brazilian_flat_angle); // 0 (absent): round
        }
      else if (const auto fw = j.find("fit_window"); fw != j.end() && fw->is_string())
        {
          double     lo = 0, hi = 0;
          const auto t = fw->get<std::string>();
          const auto b = t.find("between");
          if (b != std::string::npos &&
              std::sscanf(t.c_str() + b, "between %lf and %lf", &lo, &hi) == 2 &&
              lo >= 0 && hi > lo && hi <= 1)
            lab.fit_lo = lo, lab.fit_hi = hi;
        }
      return r;
    }

    /// Without a material file: the region's material is the `DEM region`
    /// keys', and what it must match is the pair the continuum is given.
    /// The specimen is a box of keys_probe_width x 2 widths (3D: x width
    /// deep) mean diameters at the region's grain size; the moduli are read
    /// in the low-stress window of the examples' calibrations, 5-20 % of the
    /// peak, where the bonds are intact (docs/tunnel.md, "The probe").
    Reference keys_reference(const coupling::TunnelParams &s)
    {
      Reference r;
      r.E            = s.continuum.young_modulus;
      r.nu           = s.continuum.poisson_ratio;
      const double d = s.region.mean_diameter();
      const double w = (s.dimension == 2 ? keys_probe_width_2d : keys_probe_width_3d) * d;
      r.vessel.shape = "box";
      r.vessel.W     = w;
      r.vessel.H     = 2 * w;
      if (s.dimension == 3)
        r.vessel.D = w;
      r.lab.fit_lo = 0.05;
      r.lab.fit_hi = 0.2;
      // Unbreakable bonds (verification): no peak; the test ends at a small
      // strain and the moduli are read on its linear branch.
      if (!s.region.breakable)
        r.lab.strain_limit = keys_elastic_strain_limit;
      return r;
    }

    struct Measured
    {
      std::vector<double>      E, nu, ucs, bts;
      std::vector<double>      porosity, measurement_porosity; ///< of the UCS specimens
      std::vector<std::string> modes; ///< Brazilian failure modes
      std::size_t              grains = 0;
      double                   k      = NAN; ///< grain-size factor region / lab
    };

    /// One packing's probe: its UCS specimen and (for a material file) its
    /// Brazilian disk, each fresh, as calibrate does; its messages to out.
    struct Packing
    {
      std::size_t grains   = 0;
      double      porosity = NAN, measurement_porosity = NAN;
      double      E = NAN, nu = NAN, ucs = NAN, bts = NAN;
      std::string mode;
    };

    template <int dim>
    Packing measure_packing(const dem::MaterialParams &m, const dem::VesselParams &v,
                            dem::LabTestParams lab, const bool keys, const bool breakable,
                            std::ostream &out)
    {
      // The progress lines (and ETA) calibrate prints, per packing and test.
      const std::string label = "probe seed " + std::to_string(m.seed) + " ";
      Packing           p;
      {
        auto specimen          = dem::build_specimen<dim>(m, v, &out, "probe specimen");
        p.grains               = specimen.n_grains();
        p.porosity             = specimen.porosity();
        p.measurement_porosity = specimen.measurement_porosity();
        lab.kind               = dem::TestKind::compression;
        // The keys' loading in units of the grains' dynamics: a strain
        // per step (the specimen's step: the lab test keeps it).
        if (keys)
          lab.strain_rate = keys_strain_per_step / specimen.model.timestep();
        const auto u = run_lab_test_with_progress(specimen, lab, label + "ucs");
        p.E          = u.E;
        p.nu         = u.nu;
        p.ucs        = u.peak;
      }
      std::ostringstream line; // written after the Brazilian specimen's genesis lines
      line << "probe: seed " << m.seed << ": " << p.grains << " grains, porosity "
           << p.porosity << " (measurement regions " << p.measurement_porosity << "), E "
           << p.E / 1e9 << " GPa, nu " << p.nu;
      if (keys)
        {
          if (breakable)
            line << ", UCS " << p.ucs / 1e6 << " MPa";
          out << line.str() << std::endl;
          return p;
        }
      // The Brazilian specimen of its own when the calibration had one
      // (Tests/brazilian diameter, scaled by k), else carved from v.
      auto specimen = dem::build_specimen<dim>(m, dem::brazilian_vessel(v, lab, dim),
                                               &out, "probe Brazilian specimen");
      lab.kind      = dem::TestKind::brazilian;
      const auto b  = run_lab_test_with_progress(specimen, lab, label + "brazilian");
      p.bts         = b.peak;
      p.mode        = b.failure_mode;
      out << line.str() << ", UCS " << p.ucs / 1e6 << " MPa, BTS " << p.bts / 1e6
          << " MPa (" << p.mode << ")" << std::endl;
      return p;
    }

    template <int dim>
    Measured measure(const coupling::TunnelParams &s, const Reference &ref, int seeds,
                     std::ostream &out)
    {
      Measured   r;
      const bool keys = !s.region.material;
      // The grain-size factor: the region's material is the file's with
      // every length of the microstructure multiplied by k
      // (apps/tunnel_prm.cc); the lab specimen scales with it, so it holds
      // the calibration's number of grains. The keys' specimen is already
      // at the region's scale (k = 1).
      dem::MaterialParams m = keys ? s.region.keys_material() : *s.region.material;
      r.k                 = keys ? 1.0 : m.diameter_multiplier / ref.diameter_multiplier;
      dem::VesselParams v = ref.vessel;
      v.H *= r.k;
      v.W *= r.k;
      if (dim == 3)
        v.D *= r.k;
      // The same loading in units of the grains' dynamics: with the
      // deformability method the contact stiffness does not change with
      // the grain size while the time step grows as d (mass d^dim, 2D per
      // unit thickness d^2), so the strain rate is divided by k: the same
      // strain per step, the same quasi-static quality.
      dem::LabTestParams lab = ref.lab;
      lab.strain_rate /= r.k;
      lab.brazilian_diameter *= r.k;
      lab.brazilian_thickness *= r.k;
      // E and nu read at the stresses the material file read them at: its
      // window's fractions of its UCS. A packing stronger than the file's
      // would otherwise be read higher up its curve, where more bonds have
      // broken (docs/tunnel.md, "The probe").
      std::ostringstream size; // the specimen's dimensions
      size << v.W << " x " << v.H;
      if (dim == 3)
        size << " x " << v.D;
      if (!keys)
        {
          lab.fit_window_at(ref.ucs); // lab is ref.lab: the file's fractions
          lab.validate("the material file's lab_tests and ucs", dim);
          out << "probe: lab specimen " << size.str() << " m at " << r.k
              << " x the material file's grain size, strain rate " << lab.strain_rate
              << " /s, modulus fit between " << lab.fit_stress_lo / 1e6 << " and "
              << lab.fit_stress_hi / 1e6 << " MPa deviator (the file's " << ref.lab.fit_lo
              << " .. " << ref.lab.fit_hi << " of its UCS), " << seeds
              << " packing seed(s)\n";
        }
      else
        out << "probe: no material file: the DEM region keys' material in a lab specimen "
            << size.str() << " m at the region's grain size, UCS test at "
            << keys_strain_per_step << " axial strain per time step, modulus fit between "
            << lab.fit_lo << " and " << lab.fit_hi
            << " of its peak, against the continuum's E, nu; " << seeds
            << " packing seed(s)\n";
      if (dem::own_brazilian_specimen(lab))
        out << "probe: Brazilian specimen of its own, " << lab.brazilian_diameter
            << " m across (the file's Tests/brazilian diameter x " << r.k << ")\n";
      if (lab.brazilian_flat_angle > 0)
        out << "probe: flattened Brazilian disk, flats of " << lab.brazilian_flat_angle
            << " deg (the file's Tests/brazilian flat angle)\n";
      if (!keys && !ref.lab_recorded)
        out << "probe: the material file does not record its test settings "
               "(lab_tests; written by demfem calibrate since the probe exists): "
               "the defaults of Tests are used, the comparison is weaker\n";
      // The packings side by side (apps/parallel_packings.h), each on its
      // own copies of the material and the test settings. Side by side,
      // each one's lines are kept and written in seed order once all have
      // ended, so the report does not depend on the thread count; one at a
      // time, they go out as they come.
      const bool               side_by_side = packings_at_a_time(seeds) > 1;
      std::vector<Packing>     packs(seeds);
      std::vector<std::string> lines(seeds);
      for_each_packing(seeds, [&](const int k) {
        dem::MaterialParams mk = m;
        mk.seed                = s.region.seed + k;
        std::ostringstream kept;
        packs[k] = measure_packing<dim>(mk, v, lab, keys, s.region.breakable,
                                        side_by_side ? kept : out);
        lines[k] = kept.str();
      });
      for (int k = 0; k < seeds; ++k)
        {
          out << lines[k];
          const Packing &p = packs[k];
          r.grains         = p.grains;
          r.porosity.push_back(p.porosity);
          r.measurement_porosity.push_back(p.measurement_porosity);
          r.E.push_back(p.E);
          r.nu.push_back(p.nu);
          r.ucs.push_back(p.ucs);
          if (keys)
            continue;
          r.bts.push_back(p.bts);
          r.modes.push_back(p.mode);
        }
      return r;
    }
  } // namespace

  bool run_probe(const coupling::TunnelParams &s, const std::string &material_file,
                 int seeds, const std::string &json_dir, std::ostream &out)
  {
    if (seeds < 1 || seeds > 100)
      throw dem::InputError("--probe-seeds: " + std::to_string(seeds) +
                            " packing seeds; allowed 1 .. 100");
    const bool      keys = !s.region.material;
    const Reference ref  = keys ? keys_reference(s) : read_reference(material_file);
    const Measured  m    = s.dimension == 2 ? measure<2>(s, ref, seeds, out)
                                            : measure<3>(s, ref, seeds, out);

    bool              all     = true;
    json              rows    = json::array();
    const std::string against = keys ? "continuum" : "material file";
    out << std::setprecision(4) << "probe: E, nu are the "
        << (s.dimension == 2 ? "plane-strain pair (as the " + against + "'s)"
                             : std::string("3D pair"))
        << "; mean (sd) over " << seeds << " seed(s)\n";
    // One row: the probe's mean against the file's value, judged by a
    // tolerance (relative) or, for the strengths, as two seed means of one
    // material by Welch's t test at 95 % (common/statistics.h,
    // compare_means), from both scatters (the file's packings and the
    // probe's; a file of one packing is one draw, whose scatter the probe's
    // estimates).
    auto row = [&](const std::string &name, const std::vector<double> &x, double want,
                   double rel_tol, bool by_scatter, double want_sd = NAN,
                   std::size_t want_n = 1) {
      const auto   st  = statistics::mean_interval(x);
      const double rel = (st.mean - want) / std::abs(want);
      std::string  rule, verdict;
      bool         judged = true, ok = true;
      json         se = json(), t = json(), nu = json();
      if (!std::isfinite(want))
        {
          rule   = "no material file: reported, not judged";
          judged = false;
        }
      else if (!by_scatter)
        {
          rule = "within " + std::to_string(int(std::round(100 * rel_tol))) + " %";
          ok   = std::abs(rel) <= rel_tol;
        }
      else if (x.size() > 1)
        {
          const bool         file_scatter = std::isfinite(want_sd);
          const auto         c = statistics::compare_means(st.mean, st.sd, x.size(), want,
                                                   file_scatter ? want_sd : st.sd,
                                                   file_scatter ? want_n : 1);
          std::ostringstream r;
          r << "Welch's t test at 95 %: the means within t = " << c.critical
            << " (nu = " << c.degrees_of_freedom
            << ") standard errors of their difference (" << c.standard_error << "; "
            << x.size() << " probe and "
            << (file_scatter ? std::to_string(want_n) + " file packings"
                             : std::string("1 file packing, its scatter the probe's"))
            << ")";
          rule = r.str();
          ok   = c.agree;
          se   = c.standard_error;
          t    = c.critical;
          nu   = c.degrees_of_freedom;
        }
      else
        {
          rule   = x.empty() ? "no value: not judged"
                             : "one value: not judged (--probe-seeds >= 2 measures the "
                               "scatter)";
          judged = false;
        }
      verdict = !judged ? "-" : ok ? "pass" : "FAIL";
      all     = all && ok;
      out << "  " << std::setw(4) << name << "  probe " << std::setw(10) << st.mean
          << " (" << st.sd << ")  " << against << " " << std::setw(10) << want << "  ";
      if (std::isfinite(rel))
        out << std::showpos << 100 * rel << std::noshowpos << " %  ";
      out << rule << "  " << verdict << "\n";
      rows.push_back(
          {{"property", name},
           {"probe_mean", st.mean},
           {"probe_sd", std::isfinite(st.sd) ? json(st.sd) : json()},
           {"probe_values", x},
           {keys ? "continuum" : "material_file",
            std::isfinite(want) ? json(want) : json()},
           {"material_file_sd", std::isfinite(want_sd) ? json(want_sd) : json()},
           {"standard_error", se},
           {"critical_t", t},
           {"degrees_of_freedom", nu},
           {"difference", rel},
           {"rule", rule},
           {"verdict", verdict}});
    };
    row("E", m.E, ref.E, probe_elastic_tolerance, false);
    row("nu", m.nu, ref.nu, probe_elastic_tolerance, false);
    if (!keys || s.region.breakable) // unbreakable: no strength to report
      row("UCS", m.ucs, ref.ucs, 0, true, ref.ucs_sd, ref.ucs_packings);
    // The common part of probe.json; each mode adds its own fields.
    json j;
    j["grains"]     = m.grains;
    j["seeds"]      = seeds;
    j["first_seed"] = s.region.seed;
    if (keys)
      {
        // The keys' E, nu rows are the continuum's check; no strength to
        // compare with, so no Brazilian test.
        j["material_file"]      = nullptr;
        j["compared_with"]      = "continuum";
        j["strain_per_step"]    = keys_strain_per_step;
        j["fit_window_of_peak"] = {ref.lab.fit_lo, ref.lab.fit_hi};
      }
    else
      {
        // A Brazilian disk that did not split has no tensile strength: the
        // BTS row is the split disks' (as demfem calibrate's seed mean).
        std::vector<double> split_bts;
        for (std::size_t i = 0; i < m.bts.size(); ++i)
          if (m.modes[i] == "split")
            split_bts.push_back(m.bts[i]);
        row("BTS", split_bts, ref.bts, 0, true, ref.bts_sd, ref.bts_packings);
        const std::size_t split     = split_bts.size();
        const bool        all_split = split == m.modes.size();
        all                         = all && all_split;
        out << "  Brazilian disks split: " << split << " of " << m.modes.size() << "  "
            << (all_split ? "pass" : "FAIL") << "\n";
        // The continuum gets exactly the material's constants.
        const bool continuum_ok =
            s.continuum.young_modulus == ref.E && s.continuum.poisson_ratio == ref.nu;
        all = all && continuum_ok;
        out << "  continuum E, nu = " << s.continuum.young_modulus << ", "
            << s.continuum.poisson_ratio << " (the material file's: " << ref.E << ", "
            << ref.nu << ")  " << (continuum_ok ? "pass" : "FAIL") << "\n";
        j["material_file"]        = material_file;
        j["grain_size_factor"]    = m.k;
        j["lab_tests_recorded"]   = ref.lab_recorded;
        j["fit_window_stress_Pa"] = {ref.lab.fit_lo * ref.ucs, ref.lab.fit_hi * ref.ucs};
        j["brazilian_split"]      = split;
        // Every disk's peak and failure mode (the BTS row: the split ones).
        j["brazilian_peaks_Pa"]      = m.bts;
        j["brazilian_failure_modes"] = m.modes;
      }
    // The packing beside the properties: a strength off the file's can be
    // told apart as a looser or denser packing (reported, not judged: the
    // proof is the properties).
    for (auto [name, x, want] :
         {std::tuple{"porosity", &m.porosity, ref.porosity},
          std::tuple{"measurement_porosity", &m.measurement_porosity,
                     ref.measurement_porosity}})
      {
        const auto st = statistics::mean_interval(*x);
        out << "  " << name << "  probe " << st.mean << " (" << st.sd << ")  ";
        if (std::isfinite(want))
          out << "material file " << want;
        else
          out << "no value in the material file";
        out << "  reported, not judged\n";
        j[name] = {{"probe_mean", st.mean},
                   {"probe_sd", std::isfinite(st.sd) ? json(st.sd) : json()},
                   {"probe_values", *x},
                   {"material_file", std::isfinite(want) ? json(want) : json()}};
      }
    out << "probe: " << (all ? "pass" : "FAIL") << std::endl;
    if (!json_dir.empty())
      {
        j["rows"]         = rows;
        j["continuum_E"]  = s.continuum.young_modulus;
        j["continuum_nu"] = s.continuum.poisson_ratio;
        j["pass"]         = all;
        std::ofstream f(json_dir + "/probe.json");
        f << j.dump(2) << "\n";
      }
    return all;
  }
} // namespace demfem::apps
