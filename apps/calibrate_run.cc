// The run of `demfem calibrate`: genesis, tests, material.json (see
// calibrate.h). Each test runs on a fresh specimen of the same seed (same
// packing, fistPkg §4.2), so the tests do not see each other's damage.
#include "apps/calibrate.h"
#include "apps/calibrate_output.h"
#include "apps/lab_progress.h"
#include "apps/tagged_log.h"
#include "dem/io/checkpoint.h"
#include "dem/io/vtk_output.h"
#include "dem/laws/contact_bond_law.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/laws/parallel_bond_law.h"
#include "dem/laws/smooth_joint_law.h"
#include "dem/measure/measurement.h"
#include "dem/specimen/envelope.h"
#include "dem/specimen/joint_insertion.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>

namespace demfem::apps
{
  namespace
  {
    namespace fs = std::filesystem;
    using Clock  = std::chrono::steady_clock;

    Json microparameters(const dem::MaterialParams &m, const dem::VesselParams &v)
    {
      Json j;
      j.str("type", m.type);
      Json sizes;
      for (std::size_t i = 0; i < m.sizes.size(); ++i)
        {
          const auto &p = m.sizes[i];
          Json        q;
          q.str("kind", p.gaussian ? "gaussian" : "uniform")
              .num("D_lo_m", p.d_lo)
              .num("D_hi_m", p.d_hi)
              .num("mean_m", p.mean)
              .num("sd_m", p.sd)
              .num("volume_fraction", p.volume_fraction);
          sizes.obj("piece_" + std::to_string(i), q);
        }
      j.obj("size_distribution", sizes);
      j.num("diameter_multiplier", m.diameter_multiplier)
          .num("density_kg_m3", m.density)
          .num("bulk_density", m.bulk_density)
          .num("local_damping", m.local_damping)
          .num("seed", double(m.seed))
          .num("lnm_emod_Pa", m.lnm_emod)
          .num("lnm_krat", m.lnm_krat)
          .num("lnm_fric", m.lnm_fric)
          .num("emod_Pa", m.emod)
          .num("krat", m.krat)
          .num("fric", m.fric)
          .num("igap_m", m.igap);
      if (m.type == "contactbonded")
        j.num("cb_tens_mean_Pa", m.cb_tens.mean)
            .num("cb_tens_sd_Pa", m.cb_tens.sd)
            .num("cb_tens_min_Pa", m.cb_tens.min)
            .num("cb_shears_mean_Pa", m.cb_shears.mean)
            .num("cb_shears_sd_Pa", m.cb_shears.sd)
            .num("cb_shears_min_Pa", m.cb_shears.min);
      if (m.type == "parallelbonded")
        j.num("pb_rmul", m.pb_rmul)
            .num("pb_bemod_Pa", m.pb_bemod)
            .num("pb_bkrat", m.pb_bkrat)
            .num("pb_mcf", m.pb_mcf)
            .num("pb_ten_mean_Pa", m.pb_ten.mean)
            .num("pb_ten_sd_Pa", m.pb_ten.sd)
            .num("pb_ten_min_Pa", m.pb_ten.min)
            .num("pb_coh_mean_Pa", m.pb_coh.mean)
            .num("pb_coh_sd_Pa", m.pb_coh.sd)
            .num("pb_coh_min_Pa", m.pb_coh.min)
            .num("pb_fa_deg", m.pb_fa);
      if (m.type == "flatjointed")
        j.num("fj_B", m.fj_B)
            .num("fj_G", m.fj_G)
            .num("fj_S", 1 - m.fj_B - m.fj_G)
            .num("fj_gap_mean_m", m.fj_gap.mean)
            .num("fj_gap_sd_m", m.fj_gap.sd)
            .num("fj_gap_min_m", m.fj_gap.min)
            .num("fj_Nr", m.fj_Nr)
            .num("fj_Nal", m.fj_Nal)
            .num("fj_rmul_code", m.fj_rmul_code)
            .num("fj_rmul", m.fj_rmul)
            .num("fj_ten_mean_Pa", m.fj_ten.mean)
            .num("fj_ten_sd_Pa", m.fj_ten.sd)
            .num("fj_ten_min_Pa", m.fj_ten.min)
            .num("fj_coh_mean_Pa", m.fj_coh.mean)
            .num("fj_coh_sd_Pa", m.fj_coh.sd)
            .num("fj_coh_min_Pa", m.fj_coh.min)
            .num("fj_fa_deg", m.fj_fa);
      j.str("packing", m.packing)
          .num("Pm_Pa", m.Pm)
          .num("P_tol", m.P_tol)
          .num("ratio_limit", m.ratio_limit)
          .num("cloud_porosity", m.cloud_porosity)
          .str("vessel_shape", v.shape)
          .num("vessel_H_m", v.H)
          .num("vessel_W_m", v.W)
          .num("vessel_D_m", v.D)
          .num("vessel_wall_emod_Pa", v.emod);
      return j;
    }

    template <int dim>
    void write_snapshot(const std::string &dir, const std::string &base,
                        const dem::Specimen<dim> &sp, bool contacts)
    {
      // One VTK writer at a time: packings run side by side
      // (apps/parallel_packings.h), and VTK's writers share global state
      // (its output window, object factory) that is not documented as
      // thread-safe.
      static std::mutex                 vtk_mutex;
      const std::lock_guard<std::mutex> lock(vtk_mutex);
      dem::vtkout::write_particles(dir + "/" + base + "_particles.vtp", sp.model);
      dem::vtkout::write_cracks(dir + "/" + base + "_cracks.vtp",
                                sp.model.current_cracks());
      if (contacts)
        dem::vtkout::write_contacts(dir + "/" + base + "_contacts.vtp", sp.model);
    }

    template <int dim, class Law>
    bool clone_group(const dem::ContactGroupBase<dim> &g, dem::Model<dim> &m)
    {
      const auto *c = dynamic_cast<const dem::ContactGroup<dim, Law> *>(&g);
      if (c)
        m.template add_law<Law>(c->params, "copy of the specimen", c->rule);
      return c != nullptr;
    }

    Json result_json(const dem::LabTestResult &r, int dim)
    {
      Json j;
      j.str("kind", dem::test_kind_name(r.kind))
          .str("ended_by", r.ended_by)
          .num("seating_steps", double(r.seating_steps))
          .num("loading_steps", double(r.loading_steps))
          .num("peak_Pa", r.peak)
          .num("peak_strain", r.peak_strain)
          .num("crack_initiation_Pa", r.crack_initiation)
          .num("crack_initiation_crack_count_Pa", r.crack_initiation_count)
          .num("crack_initiation_volumetric_Pa", r.crack_initiation_volumetric)
          .num("crack_initiation_lateral_Pa", r.crack_initiation_lateral)
          .num("cracks_tension_at_peak", double(r.cracks_tension_peak))
          .num("cracks_shear_at_peak", double(r.cracks_shear_peak))
          .num("cracks_tension_at_end", double(r.cracks_tension))
          .num("cracks_shear_at_end", double(r.cracks_shear));
      for (int t = 0; t < dem::n_bond_types; ++t)
        j.num(std::string("cracks_") +
                  dem::bond_type_name(static_cast<dem::BondType>(t)) + "_at_end",
              double(r.cracks_by_type[t]));
      if (r.kind == dem::TestKind::compression)
        {
          j.num("E_Pa", r.E)
              .num("nu", r.nu)
              .num("E_platen_strain_Pa", r.E_wall)
              .num("crack_damage_Pa", r.crack_damage)
              .num("peak_regions_Pa", r.peak_region)
              .num("confining_deviation", r.confining_deviation)
              .num("confining_deviation_to_peak", r.confining_deviation_to_peak)
              .num("confining_spike_to_peak", r.confining_spike_to_peak)
              .num("confining_window_s", r.confining_window)
              .num("confining_velocity_limit_m_s", r.confining_velocity_limit)
              .num("lateral_wall_segments", double(r.lateral_wall_segments));
          if (!r.confining_boundary.empty())
            j.str("confining_boundary", r.confining_boundary);
          if (dim == 2)
            j.num("E_plane_stress_Pa", r.E_ps).num("nu_plane_stress", r.nu_ps);
        }
      if (r.kind == dem::TestKind::direct_tension)
        j.num("peak_regions_Pa", r.peak_region);
      if (r.kind == dem::TestKind::brazilian)
        j.num("peak_force_N", r.peak_force)
            .num("disk_radius_m", r.R)
            .num("thickness_m", r.t)
            .str("failure_mode", r.failure_mode)
            .num("split_fraction", r.split_fraction)
            .num("failure_cracks", double(r.failure_cracks))
            .num("split_fraction_peak", r.split_fraction_peak)
            .num("split_fraction_end", r.split_fraction_end);
      return j;
    }

    std::string series_label(double Pc)
    {
      std::ostringstream o;
      o << "triaxial series " << Pc / 1e6 << " MPa";
      return o.str();
    }

  } // namespace

  // A fresh copy of the specimen right after genesis, so that every test
  // starts from the same material without repeating the packing: the
  // same law groups are created and the state comes from an HDF5
  // checkpoint (dem/io/checkpoint.h restores it bit for bit).
  template <int dim>
  std::unique_ptr<dem::Specimen<dim>> clone_specimen(const dem::Specimen<dim> &s,
                                                     const std::string        &checkpoint)
  {
    auto c                     = std::make_unique<dem::Specimen<dim>>();
    c->vessel                  = s.vessel;
    c->material                = s.material;
    c->linear_group            = s.linear_group;
    c->wall_group              = s.wall_group;
    c->bond_group              = s.bond_group;
    c->packing_pressure        = s.packing_pressure;
    c->packing_region_pressure = s.packing_region_pressure;
    c->packing_max_force       = s.packing_max_force;
    c->packing_ratio           = s.packing_ratio;
    c->packing_steps           = s.packing_steps;
    c->fj_rmul_min             = s.fj_rmul_min;
    c->fj_rmul_max             = s.fj_rmul_max;
    auto &m                    = c->model;
    m.local_damping            = s.model.local_damping;
    m.skin                     = s.model.skin;
    m.safety_factor            = s.model.safety_factor;
    m.gravity                  = s.model.gravity;
    m.check_timestep           = s.model.check_timestep;
    for (int g = 0; g < s.model.n_groups(); ++g)
      {
        const auto &grp = s.model.group(g);
        if (!(clone_group<dim, dem::LinearLaw<dim>>(grp, m) ||
              clone_group<dim, dem::FlatJointLaw<dim>>(grp, m) ||
              clone_group<dim, dem::ParallelBondLaw<dim>>(grp, m) ||
              clone_group<dim, dem::ContactBondLaw<dim>>(grp, m) ||
              clone_group<dim, dem::SmoothJointLaw<dim>>(grp, m)))
          throw std::runtime_error(std::string("calibrate: cannot copy law group ") +
                                   grp.law_name());
      }
    dem::read_checkpoint(m, checkpoint, nullptr);
    m.set_default_law(s.linear_group, s.wall_group);
    m.new_contact_law = s.model.new_contact_law; // e.g. the smooth-joint rule
    return c;
  }

  template std::unique_ptr<dem::Specimen<2>> clone_specimen(const dem::Specimen<2> &,
                                                            const std::string &);
  template std::unique_ptr<dem::Specimen<3>> clone_specimen(const dem::Specimen<3> &,
                                                            const std::string &);

  template <int dim>
  CalibrateOutcome run_calibration(const CalibrateSettings &s0)
  {
    // One packing among several side by side writes whole, tagged lines.
    TaggedLog         tagged_log("demfem calibrate: ", s0.log_tag);
    std::ostream     &log     = tagged_log.stream();
    const auto        t_start = Clock::now();
    CalibrateSettings s       = s0;
    if (s.n_grains > 0)
      dem::set_grain_count<dim>(s.mat, s.vessel, s.n_grains);
    fs::create_directories(s.out);
    const std::string vtk_dir = s.out + "/vtk";
    if (s.vtk)
      fs::create_directories(vtk_dir);

    auto build = [&](const dem::VesselParams &vessel) {
      auto sp = dem::build_specimen<dim>(s.mat, vessel, &log, s.where);
      if (s.joint)
        {
          // Smooth-jointed interface through the vessel centre + point.
          dem::JointPlane<dim> plane;
          plane.sj.sj_kn = s.joint_sj.sj_kn, plane.sj.sj_ks = s.joint_sj.sj_ks;
          plane.sj.sj_fric = s.joint_sj.sj_fric, plane.sj.sj_da = s.joint_sj.sj_da;
          plane.sj.sj_ten = s.joint_sj.sj_ten, plane.sj.sj_coh = s.joint_sj.sj_coh;
          plane.sj.sj_fa = s.joint_sj.sj_fa, plane.sj.sj_rmul = s.joint_sj.sj_rmul;
          plane.sj.dip = s.joint_sj.dip, plane.sj.ddir = s.joint_sj.ddir;
          plane.sj.bonded = s.joint_sj.bonded;
          for (int a = 0; a < dim; ++a)
            plane.point[a] = sp.vessel.center[a] + s.joint_point[a];
          int        group = -1;
          const auto n     = dem::insert_smooth_joint(sp.model, plane, group, s.where);
          log << "demfem calibrate: smooth joint inserted at " << n << " contacts\n";
        }
      return sp;
    };
    log << "demfem calibrate: genesis (" << dim << "D, " << s.mat.type << ")\n";
    const auto   t_gen      = Clock::now();
    auto         first      = std::make_unique<dem::Specimen<dim>>(build(s.vessel));
    const double genesis_s  = seconds_since(t_gen);
    const double porosity   = first->porosity();
    const double porosity_m = first->measurement_porosity();
    const double n_grains   = double(first->n_grains());
    const auto   counts     = dem::contact_counts(first->model);
    if (s.vtk)
      write_snapshot(vtk_dir, "specimen", *first, true);
    const std::string ckpt = s.out + "/specimen.h5";
    dem::write_checkpoint(first->model, ckpt, {{"parameter_file", s.where}});
    log << "demfem calibrate: " << n_grains << " grains, porosity " << porosity
        << " (measurement regions " << porosity_m << ")"
        << ", genesis " << genesis_s << " s\n";
    // The Brazilian specimen of its own (Tests/brazilian diameter), packed
    // on first use at the same grain size and seed.
    std::unique_ptr<dem::Specimen<dim>> brazilian_first;
    double                              brazilian_genesis_s = 0;
    const std::string                   brazilian_ckpt = s.out + "/specimen_brazilian.h5";
    const dem::VesselParams             brazilian_vessel =
        dem::brazilian_vessel(s.vessel, s.lab, dim);
    auto fresh = [&](const dem::LabTestParams &lp) {
      if (lp.kind != dem::TestKind::brazilian || !dem::own_brazilian_specimen(lp))
        return clone_specimen(*first, ckpt);
      if (!brazilian_first)
        {
          log << "demfem calibrate: genesis of the Brazilian specimen ("
              << brazilian_vessel.W << " m across)\n";
          const auto t    = Clock::now();
          brazilian_first = std::make_unique<dem::Specimen<dim>>(build(brazilian_vessel));
          brazilian_genesis_s = seconds_since(t);
          dem::write_checkpoint(brazilian_first->model, brazilian_ckpt,
                                {{"parameter_file", s.where}});
          if (s.vtk)
            write_snapshot(vtk_dir, "specimen_brazilian", *brazilian_first, true);
          log << "demfem calibrate: Brazilian specimen " << brazilian_first->n_grains()
              << " grains, genesis " << brazilian_genesis_s << " s\n";
        }
      return clone_specimen(*brazilian_first, brazilian_ckpt);
    };

    std::vector<std::string> truncated; // tests ended by the step limit
    std::vector<std::string> not_split; // Brazilian tests that did not split
    std::vector<std::string> not_held;  // confined tests whose P_c was not held
    // One test on a fresh specimen: history CSV, stress-strain SVG, VTK at
    // the peak and the end, and (Tests/loading rate check) the repeats at
    // half and quarter rate on the same packing (fistPkg §5.4).
    auto run_test = [&](const std::string &label, const dem::LabTestParams &lp,
                        Json &j) -> dem::LabTestResult {
      const auto name   = file_name(label);
      auto       sp     = fresh(lp);
      double     t_peak = 0, t_end = 0;
      std::function<void(const dem::Specimen<dim> &, const std::string &)> snapshot;
      if (s.vtk)
        snapshot = [&](const dem::Specimen<dim> &spec, const std::string &which) {
          (which == "peak" ? t_peak : t_end) = spec.model.time();
          write_snapshot(vtk_dir, name + "_" + which, spec, which == "end");
        };
      const auto t_test = Clock::now();
      auto       r =
          run_lab_test_with_progress(*sp, lp, s.log_tag + label, std::move(snapshot));
      const double test_s = seconds_since(t_test);
      if (s.vtk)
        for (const char *what : {"particles", "cracks"})
          {
            dem::vtkout::Collection pvd(vtk_dir + "/" + name + "_" + what + ".pvd");
            pvd.add(t_peak, vtk_dir + "/" + name + "_peak_" + what + ".vtp");
            pvd.add(t_end, vtk_dir + "/" + name + "_end_" + what + ".vtp");
          }
      dem::vtkout::write_text_atomically(s.out + "/history_" + name + ".csv",
                                         history_csv(r.history));
      // Stress-strain curve, compression positive for the compression and
      // Brazilian tests, tension positive for direct tension.
      const double        sign = lp.kind == dem::TestKind::direct_tension ? 1 : -1;
      std::vector<double> x, y;
      for (const auto &h : r.history)
        x.push_back(100 * sign * h.axial_strain),
            y.push_back(sign * h.axial_stress / 1e6);
      const std::string ylabel = lp.kind == dem::TestKind::brazilian
                                     ? "F / (pi R t)  [MPa]  (Eq. 24)"
                                     : "axial stress (platen/grip)  [MPa]";
      dem::vtkout::write_text_atomically(
          s.out + "/" + name + "_stress_strain.svg",
          svg_plot(label + " (" + std::to_string(dim) + "D, " +
                       std::to_string(std::size_t(n_grains)) + " grains)",
                   "axial strain [%]", ylabel, x, y));
      if (lp.kind == dem::TestKind::compression &&
          lp.ctype != dem::CompressionType::uniaxial_strain)
        dem::vtkout::write_text_atomically(
            s.out + "/" + name + "_strains.svg",
            compression_strains_svg(r, dim,
                                    label + ": strains and crack initiation (" +
                                        std::to_string(dim) + "D)"));
      j = result_json(r, dim);
      j.num("run_time_s", test_s)
          .num("strain_rate_1_s", lp.strain_rate)
          .num("Pc_Pa", lp.Pc);
      log << "demfem calibrate: " << label << ": peak " << r.peak / 1e6 << " MPa ("
          << r.ended_by << ", " << r.loading_steps << " steps, " << test_s << " s)";
      if (r.confining_boundary == "pressure")
        log << ", Pc as forces on the outermost grains (pressure boundary)";
      else if (r.confining_deviation == r.confining_deviation)
        log << ", Pc held within " << 100 * r.confining_deviation_to_peak
            << " % to the peak (averaged over " << r.confining_window
            << " s; single-step spikes up to " << 100 * r.confining_spike_to_peak
            << " %)";
      log << "\n";
      // A test stopped by the step limit before its post-peak end may not
      // have reached its peak: the run says so and does not end "ok".
      auto check_end = [&](const dem::LabTestResult &t, const std::string &what) {
        if (t.ended_by != "step limit")
          return;
        truncated.push_back(what);
        log << "demfem calibrate: warning: " << what << " ended at Tests/step limit ("
            << t.loading_steps
            << " steps) before its post-peak end: its peak may not be reached; "
               "raise Tests/step limit\n";
      };
      check_end(r, label);
      // A strength test that reached the strain limit with its load still at
      // its largest (peak in the last history row) measured no peak: the
      // material hardens beyond the limit. Said, not fatal: a strain limit
      // in the elastic range is a way to measure E and nu only.
      if (r.ended_by == "strain limit" && !r.history.empty() &&
          r.peak_row + 1 == r.history.size() && lp.kind != dem::TestKind::brazilian)
        log << "demfem calibrate: warning: " << label
            << " reached Tests/strain limit = " << lp.strain_limit
            << " with its load still rising: its peak " << r.peak / 1e6
            << " MPa is no strength; raise Tests/strain limit\n";
      // A Brazilian disk that did not split along its loaded diameter
      // (crushed under the platens, damaged all over, or not broken) gives
      // a peak that is no tensile strength (ISRM 1978;
      // dem/specimen/brazilian_failure.h): the run says so and is not "ok".
      if (lp.kind == dem::TestKind::brazilian && r.failure_mode != "split")
        {
          not_split.push_back(label);
          log << "demfem calibrate: warning: " << label
              << " did not split along the loaded diameter (failure mode "
              << r.failure_mode << ": ";
          if (r.failure_cracks == 0)
            log << "no crack formed after the peak";
          else
            log << r.split_fraction << " of its " << r.failure_cracks
                << " failure cracks in the split zone, below Tests/brazilian "
                   "split fraction "
                << lp.split_fraction << "; all cracks: " << r.split_fraction_peak
                << " at the peak, " << r.split_fraction_end << " at the end";
          log << "): its peak " << r.peak / 1e6
              << " MPa is no tensile strength; material.json bts is null\n";
        }
      // A triaxial peak at a confinement that was not held is not the
      // strength at P_c: the run says so and is not "ok".
      if (r.confining_deviation_to_peak > lp.confining_tolerance)
        {
          not_held.push_back(label);
          log << "demfem calibrate: warning: " << label
              << ": the confining pressure (averaged over a wave's crossing time) "
                 "deviated by "
              << 100 * r.confining_deviation_to_peak
              << " % before the peak, more than Tests/confining tolerance = "
              << 100 * lp.confining_tolerance << " % (crack bursts next to the "
              << (r.confining_boundary == "pressure" ? "pressure boundary"
                  : r.lateral_wall_segments > 1
                      ? "flexible walls"
                      : "rigid walls; in 2D Tests/lateral wall segments makes them "
                        "flexible")
              << "; in 2D Tests/confining boundary = pressure holds P_c exactly; "
                 "docs/calibrate.md, \"Confining boundary\")\n";
        }
      if (s.rate_check > 0)
        {
          // A quasi-static peak does not move when the rate is halved
          // (fistPkg §5.4); more than calibrate_rate_tolerance flags the test.
          bool   sensitive = false;
          double factor    = 1;
          for (int level = 1; level <= s.rate_check; ++level)
            {
              factor *= 0.5;
              const char        *which = level == 1 ? "half" : "quarter";
              auto               sp2   = fresh(lp);
              dem::LabTestParams l2    = lp;
              l2.strain_rate *= factor;
              l2.step_limit = std::int64_t(double(l2.step_limit) / factor);
              const auto r2 = run_lab_test_with_progress(
                  *sp2, l2, s.log_tag + label + " @ " + which + " rate");
              check_end(r2, label + " at " + which + " rate");
              const double d = (r2.peak - r.peak) / r.peak;
              sensitive      = sensitive || std::abs(d) > calibrate_rate_tolerance;
              j.num(std::string("peak_") + which + "_rate_Pa", r2.peak)
                  .num(std::string("peak_relative_change_") + which + "_rate", d);
              log << "demfem calibrate: " << label << " at " << which << " rate: peak "
                  << r2.peak / 1e6 << " MPa, relative change " << d << "\n";
            }
          j.str("quasi_static", sensitive ? "no" : "yes");
          if (sensitive)
            log << "demfem calibrate: warning: " << label
                << ": the peak moves by more than " << 100 * calibrate_rate_tolerance
                << " % at a lower loading rate; lower Tests/strain rate\n";
        }
      return r;
    };

    Json                                      tests_json;
    std::map<std::string, dem::LabTestResult> results;
    std::optional<StrengthEnvelope>           envelope;
    for (const auto &t : s.tests)
      {
        dem::LabTestParams lp = s.lab;
        lp.kind               = t.kind;
        lp.ctype              = t.ctype;
        if (t.name == "triaxial series")
          {
            // One test per confining pressure (Pc = 0: unconfined), then the
            // envelopes through the peaks (dem/specimen/envelope.h).
            StrengthEnvelope  e;
            std::vector<Json> points;
            for (double Pc : s.confining_pressures)
              {
                lp.Pc                   = Pc;
                lp.ctype                = Pc > 0 ? dem::CompressionType::confined
                                                 : dem::CompressionType::unconfined;
                const std::string label = series_label(Pc);
                Json              j;
                auto              r = run_test(label, lp, j);
                e.sigma_3.push_back(Pc);
                e.sigma_1.push_back(r.peak);
                points.push_back(j);
                results[label] = std::move(r);
              }
            e.fit(s.where);
            Json js;
            js.obj("envelope", e.json()).objs("tests", points);
            tests_json.obj(file_name(t.name), js);
            dem::vtkout::write_text_atomically(s.out + "/envelope.svg", e.svg(dim));
            log << "demfem calibrate: envelope: Mohr-Coulomb c " << e.mc.cohesion / 1e6
                << " MPa, phi " << e.mc.friction_angle * 180 / M_PI
                << " deg; Hoek-Brown sigma_ci " << e.hb.sigma_ci / 1e6 << " MPa, m_i "
                << e.hb.mi << "\n";
            envelope = e;
            continue;
          }
        if (t.ctype == dem::CompressionType::unconfined)
          lp.Pc = 0;
        Json j;
        auto r = run_test(t.name, lp, j);
        tests_json.obj(file_name(t.name), j);
        results[t.name] = std::move(r);
      }

    // material.json: the continuum's E, nu from the unconfined test (else
    // the triaxial one); strengths from their tests; null when not run.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto         get = [&](const std::string &n) -> const dem::LabTestResult         *{
      auto it = results.find(n);
      return it == results.end() ? nullptr : &it->second;
    };
    // The unconfined strength: the UCS test, else the series' Pc = 0 test.
    const dem::LabTestResult *ucs = get("ucs") ? get("ucs") : get(series_label(0));
    const dem::LabTestResult *el  = ucs ? ucs : get("triaxial");
    const dem::LabTestResult *dt  = get("direct tension");
    // A Brazilian peak is a BTS only when the disk split (above).
    const dem::LabTestResult *brazilian = get("brazilian");
    const dem::LabTestResult *bts =
        brazilian && brazilian->failure_mode == "split" ? brazilian : nullptr;
    auto ratio = [&](const dem::LabTestResult *a, double dem::LabTestResult::*x,
                     const dem::LabTestResult *b) {
      return a && b && b->peak > 0 ? a->*x / b->peak : nan;
    };
    // Post-peak brittleness of the unconfined test (calibrate_output.h).
    auto ucs_post_peak = [](const dem::LabTestResult &r) {
      std::vector<double> e, q;
      for (const auto &h : r.history)
        e.push_back(h.axial_strain), q.push_back(h.axial_stress);
      return post_peak_strain_ratio(e, q);
    };
    Json mat;
    mat.num("dim", dim)
        .num("n_grains", n_grains)
        .num("porosity", porosity)
        .num("measurement_porosity", porosity_m)
        .num("E", el ? el->E : nan)
        .num("nu", el ? el->nu : nan)
        .num("E_plane_stress", el && dim == 2 ? el->E_ps : nan)
        .num("nu_plane_stress", el && dim == 2 ? el->nu_ps : nan)
        .num("ucs", ucs ? ucs->peak : nan)
        .num("triaxial_strength", get("triaxial") ? get("triaxial")->peak : nan)
        .num("confining_pressure", s.lab.Pc)
        .num("bts", bts ? bts->peak : nan)
        .str("bts_failure_mode", brazilian ? brazilian->failure_mode : "not run")
        .num("bts_split_fraction", brazilian ? brazilian->split_fraction : nan)
        .num("direct_tension", dt ? dt->peak : nan)
        .num("direct_tension_regions", dt ? dt->peak_region : nan)
        .num("crack_initiation", el ? el->crack_initiation : nan)
        .str("crack_initiation_method",
             dem::crack_initiation_method_name(s.lab.crack_initiation_method))
        .num("crack_initiation_crack_count", el ? el->crack_initiation_count : nan)
        .num("crack_initiation_volumetric", el ? el->crack_initiation_volumetric : nan)
        .num("crack_initiation_lateral", el ? el->crack_initiation_lateral : nan)
        .num("crack_damage", el ? el->crack_damage : nan);
    Json ratios;
    ratios
        .num("crack_initiation_to_ucs",
             ratio(ucs, &dem::LabTestResult::crack_initiation, ucs))
        .num("crack_damage_to_ucs", ratio(ucs, &dem::LabTestResult::crack_damage, ucs))
        .num("direct_tension_to_bts", ratio(dt, &dem::LabTestResult::peak, bts))
        .num("ucs_to_bts", ratio(ucs, &dem::LabTestResult::peak, bts))
        .num("post_peak_strain_ratio", ucs ? ucs_post_peak(*ucs) : nan);
    mat.obj("ratios", ratios);
    if (envelope)
      mat.obj("envelope", envelope->json());
    Json units;
    units.str("E", "Pa")
        .str("nu", "1")
        .str("E_plane_stress", "Pa")
        .str("nu_plane_stress", "1")
        .str("ucs", "Pa")
        .str("triaxial_strength", "Pa")
        .str("confining_pressure", "Pa")
        .str("bts", "Pa")
        .str("bts_split_fraction", "1")
        .str("direct_tension", "Pa")
        .str("direct_tension_regions", "Pa")
        .str("crack_initiation", "Pa")
        .str("crack_initiation_crack_count", "Pa")
        .str("crack_initiation_volumetric", "Pa")
        .str("crack_initiation_lateral", "Pa")
        .str("crack_damage", "Pa")
        .str("porosity", "1")
        .str("measurement_porosity", "1")
        .str("n_grains", "1");
    mat.obj("units", units);
    mat.str("elastic_constants",
            dim == 2
                ? "E, nu: plane-strain pair for the continuum (docs/architecture.md: nu "
                  "= nu'/(1+nu'), "
                  "E = E'(1-nu^2)) from the plane-stress fit E', nu' (fistPkg Eq. 19)"
                : "E, nu: fistPkg Eq. 18");
    mat.str("fit_window", "secant least squares between " + std::to_string(s.lab.fit_lo) +
                              " and " + std::to_string(s.lab.fit_hi) +
                              " of the peak deviator");
    // The test settings, so that the same tests can be repeated on this
    // material elsewhere (demfem tunnel --probe, docs/tunnel.md).
    Json lab;
    lab.num("strain_rate_per_s", s.lab.strain_rate)
        .num("fit_window_low", s.lab.fit_lo)
        .num("fit_window_high", s.lab.fit_hi)
        .num("load_fraction", s.lab.load_fraction)
        .num("strain_limit", s.lab.strain_limit)
        .num("step_limit", double(s.lab.step_limit))
        .num("history_interval", s.lab.history_interval)
        .num("seating_ratio_limit", s.lab.ratio_limit)
        .num("seating_step_limit", double(s.lab.seat_step_limit))
        .num("platen_friction", s.lab.platen_friction)
        .num("split_fraction", s.lab.split_fraction)
        .num("confining_tolerance", s.lab.confining_tolerance)
        .num("servo_velocity_limit_m_s", s.lab.servo.v_limit)
        .num("lateral_wall_segments", s.lab.lateral_segments)
        .str("confining_boundary", s.lab.pressure_boundary ? "pressure" : "walls")
        .num("time_step_safety", s.lab.timestep_safety)
        .num("brazilian_diameter_m", s.lab.brazilian_diameter)
        .num("brazilian_flat_angle_deg", s.lab.brazilian_flat_angle)
        .num("brazilian_thickness_m",
             dim == 3 && dem::own_brazilian_specimen(s.lab) ? brazilian_vessel.D : 0.0);
    mat.obj("lab_tests", lab);
    mat.obj("microparameters", microparameters(s.mat, s.vessel));
    dem::vtkout::write_text_atomically(s.out + "/material.json", mat.text() + "\n");

    Json sum;
    sum.str("command", "calibrate")
        .str("status",
             calibration_status(truncated.size(), not_split.size(), not_held.size()))
        .str("parameter_file", s.where)
        .num("dim", dim)
        .num("n_grains", n_grains)
        .num("porosity", porosity)
        .num("measurement_porosity", porosity_m)
        .num("coordination", counts.coordination)
        .num("bond_coordination", counts.bond_coordination)
        .num("genesis_s", genesis_s);
    if (brazilian_first)
      sum.num("brazilian_n_grains", double(brazilian_first->n_grains()))
          .num("brazilian_genesis_s", brazilian_genesis_s);
    sum.num("wall_time_s", seconds_since(t_start));
    sum.obj("tests", tests_json);
    dem::vtkout::write_text_atomically(s.out + "/summary.json", sum.text() + "\n");
    for (const auto &f : {ckpt, brazilian_ckpt})
      {
        fs::remove(f);
        fs::remove(f + ".prev");
      }
    return calibration_outcome(s.out, seconds_since(t_start), truncated.size(),
                               not_split.size(), not_held.size());
  }

  template CalibrateOutcome run_calibration<2>(const CalibrateSettings &);
  template CalibrateOutcome run_calibration<3>(const CalibrateSettings &);
} // namespace demfem::apps
