#include "coupling/tunnel_run.h"

#include "coupling/in_situ_servo.h"
#include "coupling/tunnel_frames.h"
#include "coupling/tunnel_history.h"
#include "coupling/tunnel_measures.h"
#include "coupling/tunnel_phase.h"
#include "dem/io/checkpoint.h"
#include "dem/io/vtk_output.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace demfem::coupling
{
  using dem::Vec;

  volatile std::sig_atomic_t tunnel_stop_requested = 0;

  namespace
  {
    // A breakable section with a free core shorter than this many mean
    // grain diameters gets a warning (set_up): the measured six-grain
    // section (two free) read 4 % of the plane-strain damaged area; ten
    // free diameters are several damage depths at a/d = 4 (0.2-0.3 m for
    // d = 0.1 m), the least for which its ends could not hold the zone.
    constexpr double min_free_section_diameters = 10;

    // An elastic crack-initiation zone shallower than this many mean grain
    // diameters gets a warning (warn_if_initiation_zone_unresolved). At
    // a/d = 10 the default example's zones of 0.9-1.9 diameters all read
    // the same depth, the second grain layer; at a/d = 20 zones of 1.8, 2.8
    // and 3.7 diameters read -4, +33 and +3 % (one packing each, which
    // scatters by 20-30 %). Three is the conservative side of that.
    constexpr double min_initiation_zone_grains = 3;

    // The continuum of a tunnel section (3D) has the tunnel through it.
    ContinuumParams with_tunnel(const TunnelParams &p)
    {
      ContinuumParams c = p.continuum;
      c.tunnel_radius   = p.tunnel_radius;
      return c;
    }

  } // namespace

  void TunnelParams::validate(const std::string &w) const
  {
    const double inf = HUGE_VAL;
    if (dimension != 2 && dimension != 3)
      throw dem::InputError(w + ": Problem/dimension = " + std::to_string(dimension) +
                            " (allowed: 2, 3)");
    region.validate(w, dimension);
    dem::check_range(w, "Tunnel/radius", tunnel_radius, 0, inf, true);
    if (tunnel_radius + 3 * region.d_hi > region.radius)
      throw dem::InputError(w + ": Tunnel/radius (" + std::to_string(tunnel_radius) +
                            " m) must be smaller than DEM region/radius (" +
                            std::to_string(region.radius) +
                            " m) by at least three of the largest grains (" +
                            std::to_string(3 * region.d_hi) + " m)");
    coupling.validate(w);
    with_tunnel(*this).validate(w, dimension, region.radius, coupling);
    dem::check_range(w, "Tunnel/excavation stages", stages, 1, 1000);
    dem::check_range(w, "Tunnel/damage link length", damage_link_diameters,
                     DamageZone::min_link_grain_diameters,
                     DamageZone::max_link_grain_diameters);
    dem::check_range(w, "Coupling/ramp crossing times", ramp_crossing_times, 0,
                     max_ramp_crossing_times, true);
    // The servo must stop inside the tolerance the run is judged by.
    dem::check_range(w, "Tunnel/in situ servo tolerance", in_situ_servo_tolerance, 0,
                     in_situ_tolerance, false, true);
    if (coupling.variant == "slaved-layer" &&
        tunnel_radius + 3 * region.d_hi >
            region.radius - coupling.overlap_grains * region.mean_diameter())
      throw dem::InputError(
          w + ": Tunnel/radius (" + std::to_string(tunnel_radius) +
          " m) must be smaller than the free part of the DEM region (DEM region/radius "
          "minus Coupling/overlap grains mean diameters, " +
          std::to_string(region.radius -
                         coupling.overlap_grains * region.mean_diameter()) +
          " m) by at least three of the largest grains");
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        if (!std::isfinite(sigma0(i, j)))
          throw dem::InputError(w + ": Tunnel/in situ stress must be finite");
  }

  namespace
  {
    /// Thrown at a step boundary after the stop checkpoint was written.
    struct Interrupted
    {
    };

    /// The .prm text without the keys that do not change the results
    /// (output directory, checkpoint interval): what a restart compares.
    std::string physics_text(const std::string &prm)
    {
      std::istringstream in(prm);
      std::string        line, r;
      while (std::getline(in, line))
        if (line.find("output directory") == std::string::npos &&
            line.find("checkpoint interval") == std::string::npos)
          r += line + "\n";
      return r;
    }

    std::string meta_get(const std::map<std::string, std::string> &m,
                         const std::string &k, const std::string &file)
    {
      const auto it = m.find(k);
      if (it == m.end())
        throw dem::InputError("restart: checkpoint " + file + " has no entry '" + k +
                              "' (not written by demfem tunnel?)");
      return it->second;
    }

    /// The tunnel workflow (docs/tunnel.md): set up, install the in-situ
    /// stress, excavate stage by stage, equilibrate, report. Each phase is
    /// run_phase (tunnel_phase.h); this class is its hooks: history rows and
    /// VTK frames, progress, checkpoints and interruption at step boundaries.
    template <int dim>
    class TunnelWorkflow
    {
    public:
      TunnelWorkflow(const TunnelParams &pp, std::ostream &o)
          : p(pp)
          , out(o)
          , model(make_coupled_model<dim>(pp.region, with_tunnel(pp), pp.coupling,
                                          MPI_COMM_WORLD))
          , m(*model)
          , dir(pp.output_directory)
          , measures(m, pp.tunnel_radius, pp.damage_link_diameters)
          , history(dir + "/history.csv")
          , frames(dir)
      {
        measures.compare_with_elastic_initiation(pp.sigma0, pp.crack_initiation,
                                                 plane_strain_nu_zz());
      }

      TunnelResult run()
      {
        TunnelResult r;
        set_up(r);
        const int start = phase_index; // 0 for a fresh run, else the checkpoint's
        try
          {
            if (start == 0)
              {
                install_in_situ();
                measures.excavate(m);
              }
            for (int s = std::max(1, start); s <= p.stages; ++s)
              excavation_stage(s);
            if (start <= p.stages + 1)
              equilibrate();
            phase_index = p.stages + 2;
          }
        catch (const Interrupted &)
          {
            history.save();
            r.interrupted = true;
            r.checkpoint  = last_checkpoint;
            r.steps       = m.dem.step_count();
            return r;
          }
        catch (const dem::InstabilityError &e)
          {
            r.diverged  = true;
            r.diagnosis = e.what();
            out << "demfem tunnel: DIVERGED in phase '" << phase << "': " << e.what()
                << std::endl;
          }
        report(r);
        return r;
      }

      // ---- the hooks of run_phase (tunnel_phase.h) ------------------------
      double at_boundary(const PhaseProgress &at)
      {
        const auto s0    = m.dem.step_count();
        const bool stop  = tunnel_stop_requested != 0 || s0 - step0 == p.stop_at_step;
        double     spent = 0;
        if (stop || (p.checkpoint_interval > 0 && at.iteration > 1 &&
                     s0 % p.checkpoint_interval == 0))
          {
            const auto t = std::chrono::steady_clock::now();
            checkpoint(at);
            spent = seconds_since(t);
          }
        if (stop)
          {
            out << "demfem tunnel: interrupted at step " << s0
                << "; checkpoint written to " << last_checkpoint << std::endl;
            throw Interrupted{};
          }
        return spent;
      }

      double output(std::int64_t step)
      {
        const bool row = step % p.history_interval == 0;
        const bool vtk = p.vtk_interval > 0 && step % p.vtk_interval == 0;
        if (!row && !vtk)
          return 0;
        const auto t = std::chrono::steady_clock::now();
        if (row)
          history.record(m, phase, measures);
        if (vtk)
          write_frame();
        return seconds_since(t);
      }

      static double seconds_since(std::chrono::steady_clock::time_point t)
      {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t)
            .count();
      }

      void progress_line(double ur)
      {
        const double el =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const auto   n   = m.dem.step_count() - step0;
        const double eta = n > 0 ? el / n * std::max<std::int64_t>(0, budget - n) : 0;
        out << "[" << phase << "] step " << n << "  t = " << std::setprecision(4)
            << m.dem.time() << " s  ratio = " << ur
            << "  cracks = " << measures.cracks(-1) << "  ETA <= " << std::setprecision(3)
            << eta << " s" << std::endl;
        // The damage zone reaching the coupling boundary means the region is
        // too small for the scene: the continuum cannot crack (docs/
        // architecture.md, "Speed-versus-accuracy study"). Isolated cracks
        // there are reported once, apart.
        const auto near = measures.cracks_near_interface();
        if (!warned_isolated_near_interface && near[0] > near[1])
          {
            warned_isolated_near_interface = true;
            out << "note: " << near[0] - near[1]
                << " isolated excavation crack(s) (not connected to the wall) within "
                   "two grain diameters of the coupling boundary (r > "
                << measures.interface_band_radius() << " m)" << std::endl;
          }
        if (!warned_region_too_small && near[1] > 0)
          {
            warned_region_too_small = true;
            out << "warning: the damage zone (cracks connected to the wall) is within "
                   "two grain diameters of the coupling boundary (r > "
                << measures.interface_band_radius()
                << " m): the DEM region is too small for this damage; enlarge DEM "
                   "region/radius or use 'auto'"
                << std::endl;
          }
      }

    private:
      const TunnelParams                &p;
      std::ostream                      &out;
      std::unique_ptr<CoupledModel<dim>> model;
      CoupledModel<dim>                 &m;
      std::string                        dir;
      TunnelMeasures<dim>                measures;
      TunnelHistory<dim>                 history;
      TunnelFrames<dim>                  frames;
      // The workflow's position (docs/architecture.md, "Checkpoints and
      // restart"): the phase index (0 in-situ, 1..stages excavation stage,
      // stages+1 equilibrium, stages+2 done), the phase's name and progress,
      // whether it resumes from a checkpoint, the phases ended so far.
      int                                   phase_index = 0;
      std::string                           phase       = "build";
      PhaseProgress                         at;
      bool                                  resuming = false;
      std::vector<PhaseRecord>              phases;
      std::string                           last_checkpoint;
      bool                                  warned_region_too_small        = false;
      bool                                  warned_isolated_near_interface = false;
      std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
      std::int64_t budget  = 0; // expected coupled steps for the ETA (upper bound)
      std::int64_t n_ramp  = 0; // steps of the in-situ ramp (its duration / dt)
      std::int64_t n_servo = 0; // steps of an in-situ servo correction
      std::unique_ptr<InSituServo> servo;     // made in set_up (needs eps0)
      std::int64_t                 step0 = 0; // steps of the packing

      // The elastic zone where sigma1 - sigma3 reaches the material's crack
      // initiation (coupling/initiation_zone.h) is where the damage
      // starts; fewer than min_initiation_zone_grains grain diameters deep,
      // the damage-zone depth may count grain layers: measured on the
      // default example at a/d = 10, 0.235 m at five in-situ stresses whose
      // zones are 0.09-0.19 m deep (docs/tunnel.md, "Default example").
      // The Poisson ratio of a 3D model's plane-strain sigma_zz for the
      // elastic zones (coupling/kirsch.h); 2D: none (< 0).
      double plane_strain_nu_zz() const
      {
        return dim == 3 ? p.continuum.poisson_ratio : -1.0;
      }

      void warn_if_initiation_zone_unresolved() const
      {
        if (!p.region.breakable || p.crack_initiation.empty())
          return;
        const auto &[key, ci] = p.crack_initiation.front();
        const double d        = p.region.mean_diameter();
        const double R =
            kirsch::damage_radius(p.sigma0, p.tunnel_radius, ci, plane_strain_nu_zz());
        const double depth = R - p.tunnel_radius;
        if (R < HUGE_VAL && depth > 0 && depth < min_initiation_zone_grains * d)
          out << "warning: the elastic zone where sigma1 - sigma3 reaches the material's "
              << key << " (" << ci / 1e6 << " MPa) is " << depth << " m deep, "
              << depth / d << " mean grain diameters: below "
              << min_initiation_zone_grains
              << " the damage-zone depth is a count of grain layers; lower DEM "
                 "region/grain diameter"
              << std::endl;
      }

      // ---- the algorithm --------------------------------------------------
      void set_up(TunnelResult &r)
      {
        check_restart(p); // a foreign checkpoint: refused before anything is written
        std::filesystem::create_directories(dir);
        out << "demfem tunnel: building the DEM region and the continuum" << std::endl;
        // Below about 10 grains per tunnel radius a damage zone of a
        // fraction of the radius is one or two grains deep: the depth is
        // then a count of grains more than a measure (docs/tunnel.md,
        // "Grain-size scaling").
        if (const double ad = p.tunnel_radius / p.region.mean_diameter(); ad < 10)
          out << "warning: a/d = " << ad << " (tunnel radius " << p.tunnel_radius
              << " m over the mean grain diameter " << p.region.mean_diameter()
              << " m) is below 10: too coarse to resolve a damage zone of a fraction "
                 "of the radius; lower DEM region/grain diameter"
              << std::endl;
        warn_if_initiation_zone_unresolved();
        m.build(&out);
        // A section's grains are slaved to the continuum over h at both ends,
        // so only t - 2h is free, held by elastic rock beyond its ends
        // (docs/study.md, "3D: the breakable mode": 2 free diameters read 4 %
        // of the plane-strain damaged area). Not refused: the section is the
        // right model of a local feature, not of plane-strain damage.
        if (const double free = p.region.slab_thickness - 2 * m.end_overlap(),
            d                 = p.region.mean_diameter();
            m.section() && p.region.breakable && free < min_free_section_diameters * d)
          out << "warning: the section's free core between its slaved end layers is "
              << free / d << " grain diameters long (DEM region/slab thickness "
              << p.region.slab_thickness << " m less 2 x " << m.end_overlap()
              << " m): held by the elastic rock beyond its ends, it cracks far less than "
                 "a plane-strain tunnel (measured: 4 % of the damaged area at 2 free "
                 "diameters); for plane-strain damage use the slab (Continuum/axial "
                 "extension = 0) or a section of at least "
              << min_free_section_diameters << " free diameters" << std::endl;
        m.set_insitu(p.sigma0);
        r.n_fem_dofs = m.n_fem_dofs();
        // The ramp's duration is physical; its step count follows from dt.
        r.ramp_crossing_time = p.region.crossing_time();
        r.ramp_duration      = p.ramp_crossing_times * r.ramp_crossing_time;
        n_ramp               = ramp_steps(r.ramp_duration, m.dt());
        r.ramp_steps         = n_ramp;
        out << "in-situ ramp: " << r.ramp_duration << " s (" << p.ramp_crossing_times
            << " crossing times of the region, 2 R / sqrt(E*/rho) = "
            << r.ramp_crossing_time << " s), " << n_ramp << " steps" << std::endl;
        // A servo correction is small and applied on the affine path: one
        // crossing time (coupling/in_situ_servo.h).
        n_servo = ramp_steps(r.ramp_crossing_time, m.dt());
        servo   = std::make_unique<InSituServo>(
            servo_on() ? p.in_situ_servo_tolerance : 0.0, p.sigma0,
            m.insitu_strain_in_plane(), p.continuum.young_modulus,
            p.continuum.poisson_ratio);
        if (p.in_situ_servo_tolerance > 0 && !servo_on())
          out << "note: no in-situ servo (Tunnel/in situ servo tolerance) with "
              << m.checkpoint_tag()
              << ": its interface does not follow the affine in-situ path; the "
                 "region's stress is the kinematic installation's"
              << std::endl;
        budget = n_ramp + p.phase_step_limit * (2 + p.stages);
        step0  = m.dem.step_count();
        if (!p.restart_file.empty())
          restore(p.restart_file);
        else
          {
            history.start();
            write_frame();
          }
      }

      /// The in-situ stress (docs/tunnel.md, "In-situ stress installation"):
      /// phase "in-situ" installs it over Coupling/ramp crossing times
      /// (coupled_model.h)
      /// and relaxes it to equilibrium with bond breakage suspended, so the
      /// region reaches sigma0 as the elastic equilibrium a quasi-static
      /// loading path would reach (the bonded material is linear elastic
      /// until a bond breaks); phase "in-situ cracking" then lets the
      /// strengths act at sigma0 and cycles to equilibrium again: the bonds
      /// loaded beyond their strength at sigma0 break, and only those (the
      /// release of the affine path at rest broke 4-10 times more of the
      /// weak bonds of a strength spread than a lab test reaching the same
      /// stress). The region's stress is measured before excavation.
      ///
      /// With the servo (coupling/in_situ_servo.h) the continuum stays held
      /// on the affine path through "in-situ" and the corrections
      /// "in-situ servo k", and phase "in-situ release" relaxes the model
      /// after it lets the continuum go, all with bond breakage suspended.
      void install_in_situ()
      {
        // A restart resumes the phase it stopped in (the phases before it
        // are done; their results are in the checkpoint).
        const std::string resume_at = resuming ? phase : std::string();
        const bool        servoed   = servo_on();
        if (resume_at.empty() || resume_at == "in-situ")
          {
            phase = "in-situ";
            m.dem.suspend_bond_breakage(true);
            m.hold_continuum(servoed);
            run_and_record(PhaseLimits{n_ramp, n_ramp + p.phase_step_limit,
                                       p.phase_time_limit, p.ratio_tolerance},
                           [&](std::int64_t n) {
                             m.set_load_factor(std::min(1.0, double(n) / n_ramp));
                           });
          }
        if (servoed && resume_at != "in-situ release" && resume_at != "in-situ cracking")
          run_servo(resume_at.rfind("in-situ servo", 0) == 0);
        if (servoed && resume_at != "in-situ cracking")
          {
            phase = "in-situ release";
            m.dem.suspend_bond_breakage(true);
            m.hold_continuum(false);
            run_and_record(
                PhaseLimits{0, p.phase_step_limit, p.phase_time_limit, p.ratio_tolerance},
                [](std::int64_t) {});
          }
        phase = "in-situ cracking";
        m.dem.suspend_bond_breakage(false);
        run_and_record(
            PhaseLimits{0, p.phase_step_limit, p.phase_time_limit, p.ratio_tolerance},
            [](std::int64_t) {},
            phases.empty() ? 0.0 : phases.back().kinetic_energy_peak);
        measures.measure_in_situ_stress();
        write_frame();
      }

      /// The servo's corrections (coupling/in_situ_servo.h): measure the
      /// centre-disk stress at equilibrium, correct the interface strain over
      /// n_servo steps, relax; `resumed_ramp`: a restart inside a
      /// correction, which continues first.
      void run_servo(bool resumed_ramp)
      {
        m.dem.suspend_bond_breakage(true);
        m.hold_continuum(true);
        for (;; resumed_ramp = false)
          {
            if (!resumed_ramp)
              {
                const Eigen::Matrix2d sr   = measures.centre_stress_in_plane();
                const bool            done = servo->record(sr, m.interface_strain());
                out << "in-situ servo: centre-disk stress (" << sr(0, 0) / 1e6 << ", "
                    << sr(1, 1) / 1e6 << ", " << sr(0, 1) / 1e6 << ") MPa, error "
                    << 100 * servo->iterations().back().error << " % (tolerance "
                    << 100 * servo->tolerance() << " %)" << std::endl;
                if (done)
                  break;
                servo->from = m.interface_strain();
                servo->to   = servo->next_strain();
                phase = "in-situ servo " + std::to_string(servo->iterations().size());
              }
            run_and_record(PhaseLimits{n_servo, n_servo + p.phase_step_limit,
                                       p.phase_time_limit, p.ratio_tolerance},
                           [&](std::int64_t n) {
                             const double f = std::min(1.0, double(n) / n_servo);
                             m.set_interface_strain(servo->from +
                                                    f * (servo->to - servo->from));
                           });
          }
        if (!servo->converged())
          out << "warning: the in-situ servo stopped after "
              << InSituServo::max_iterations << " corrections at an error of "
              << 100 * servo->iterations().back().error
              << " % (Tunnel/in situ servo tolerance " << 100 * servo->tolerance()
              << " %)" << std::endl;
        if (servo->relative_strain() > InSituServo::contrast_warning)
          out << "warning: the in-situ servo's interface strain is "
              << 100 * servo->relative_strain()
              << " % of the in-situ strain: the region's stiffness is not the "
                 "continuum's (region / continuum: lambda + mu "
              << servo->stiffness_ratios()[0] << ", mu " << servo->stiffness_ratios()[1]
              << "); check that the continuum takes the material file's E and nu"
              << std::endl;
      }

      bool servo_on() const
      {
        return p.in_situ_servo_tolerance > 0 && m.follows_affine_path();
      }

      /// Stage s of Tunnel/excavation stages: the removed core's support is
      /// relaxed to 1 - s/stages of its value (a section's continuum tunnel
      /// wall with it) and the model cycled to equilibrium.
      void excavation_stage(int s)
      {
        phase_index = s;
        phase       = "excavation " + std::to_string(s) + "/" + std::to_string(p.stages);
        const double rem = 1.0 - double(s) / p.stages;
        m.set_excavation_release(rem);
        if (!resuming) // a resumed stage has its loads in the checkpoint
          measures.relax_core_support(m, rem);
        // 200 steps at least: a stage's load change takes a few wave
        // transits of the region to act.
        run_and_record(
            PhaseLimits{200, p.phase_step_limit, p.phase_time_limit, p.ratio_tolerance},
            [](std::int64_t) {});
        write_frame();
      }

      void equilibrate()
      {
        phase_index = p.stages + 1;
        phase       = "equilibrium";
        // The final equilibrium continues the last stage: its kinetic energy
        // is measured against that stage's peak (a fresh peak would be the
        // residual motion of an equilibrated model, and decaying that by
        // kinetic_energy_target again cost the default example 5 500 steps).
        run_and_record(
            PhaseLimits{0, p.phase_step_limit, p.phase_time_limit, p.ratio_tolerance},
            [](std::int64_t) {},
            phases.empty() ? 0.0 : phases.back().kinetic_energy_peak);
      }

      template <class Load>
      void run_and_record(const PhaseLimits &limits, Load &&load,
                          double continued_peak = 0)
      {
        const bool resumed = resuming;
        resuming           = false;
        const PhaseRecord ph =
            run_phase(m, phase, limits, at, resumed, continued_peak, load, *this);
        at.time_start = ph.time_start;
        phases.push_back(ph);
        if (!ph.equilibrated)
          out << "warning: phase '" << phase << "' ended at its "
              << (ended_at_time_limit(ph, p.phase_time_limit) ? "time limit ("
                                                              : "step limit (")
              << ph.steps << " steps, " << ph.time_end - ph.time_start
              << " s) before equilibrium: unbalanced ratio " << ph.unbalanced_ratio
              << " (target " << p.ratio_tolerance << ")" << std::endl;
      }

      /// Outputs, the final checkpoint, the result and its status.
      void report(TunnelResult &r)
      {
        if (!r.diverged)
          {
            write_frame();
            if (p.checkpoint_interval > 0) // final state, e.g. to continue
              checkpoint(PhaseProgress{0, 0.0, at.time_start});
          }
        history.save();
        fill_result(r);
        if (!r.diverged)
          dem::vtkout::write_text_atomically(dir + "/wall_displacement.csv",
                                             measures.wall_displacement_csv());
        assess_outcome(r);
        dem::vtkout::write_text_atomically(dir + "/summary.json",
                                           summary_json(r).dump(2) + "\n");
      }

      void write_frame()
      {
        history.save();
        if (p.write_vtk)
          frames.write(m);
      }

      // ---- checkpoints (docs/architecture.md, "Checkpoints and restart") --
      // The workflow's numbers (dem/io/state_archive.h): one function for
      // saving and loading. `step`: the DEM step of the checkpoint
      // (history.csv is trimmed to it on restart).
      void serialize(dem::StateArchive &ar, PhaseProgress &progress, std::int64_t &step)
      {
        ar.io("run.phase_index", phase_index);
        ar.io("run.iteration", progress.iteration);
        ar.io("run.step", step);
        ar.io("run.kinetic_energy_peak", progress.kinetic_energy_peak);
        ar.io("run.phase_start_time", progress.time_start);
        measures.serialize(ar);
        servo->serialize(ar);
      }

      void checkpoint(PhaseProgress progress)
      {
        // Text in the metadata, numbers as named datasets.
        std::map<std::string, std::string> md;
        md["prm"]              = p.prm_text;
        md["coupling.variant"] = m.checkpoint_tag();
        md["run.phase"]        = phase;
        md["run.phases"]       = phases_to_text(phases);
        md["run.frames"]       = frames.to_text();
        dem::NamedArrays state;
        auto             ar   = dem::StateArchive::saving(state);
        std::int64_t     step = m.dem.step_count();
        m.serialize(ar);
        serialize(ar, progress, step);
        history.save();
        last_checkpoint = dir + "/checkpoint.h5";
        dem::write_checkpoint(m.dem, last_checkpoint, md, state);
      }

      void restore(const std::string &file)
      {
        std::map<std::string, std::string> md;
        dem::NamedArrays                   state;
        dem::read_checkpoint(m.dem, file, &md, &state);
        if (meta_get(md, "coupling.variant", file) != m.checkpoint_tag())
          throw dem::InputError("restart: checkpoint " + file + " was written by the '" +
                                meta_get(md, "coupling.variant", file) +
                                "' coupling, this run uses '" + m.checkpoint_tag() + "'");
        auto         ar   = dem::StateArchive::loading(state, file);
        std::int64_t step = 0;
        m.serialize(ar);
        serialize(ar, at, step);
        phase = meta_get(md, "run.phase", file);
        try
          {
            phases = phases_from_text(meta_get(md, "run.phases", file));
          }
        catch (const std::invalid_argument &e)
          {
            throw dem::InputError("restart: checkpoint " + file + ": " + e.what());
          }
        frames.from_text(meta_get(md, "run.frames", file));
        resuming = true;
        history.restore(std::filesystem::absolute(file).parent_path() / "history.csv",
                        step);
        out << "demfem tunnel: restarted from " << file << " at step " << step << " ("
            << phase << ")" << std::endl;
      }

      // Everything the summary, the study and the outcome checks need.
      void fill_result(TunnelResult &r) const
      {
        r.dimension = dim;
        r.variant   = m.variant();
        r.scheme    = m.scheme();
        if (dim == 3)
          {
            r.embedding       = m.section() ? "section" : "slab";
            r.slab_thickness  = p.region.slab_thickness;
            r.axial_extension = p.continuum.axial_extension;
          }
        r.sigma0            = p.sigma0;
        r.in_situ_tolerance = p.in_situ_tolerance;
        r.servo.tolerance   = servo->tolerance();
        for (const auto &it : servo->iterations())
          r.servo.errors.push_back(it.error);
        r.servo.converged        = servo->converged();
        r.servo.interface_strain = m.interface_strain();
        r.servo.relative_strain  = servo->relative_strain();
        r.servo.stiffness_ratios = servo->stiffness_ratios();
        r.phase_time_limit       = p.phase_time_limit;
        r.ratio_tolerance        = p.ratio_tolerance;
        r.phases                 = phases;
        r.checkpoint             = last_checkpoint;
        if constexpr (dim == 2)
          r.positions = m.dem.particles.x;
        else
          r.positions_3d = m.dem.particles.x;
        r.n_particles                   = m.dem.particles.size();
        r.n_contacts                    = m.dem.n_contacts();
        r.steps                         = m.dem.step_count();
        r.packing_steps                 = step0;
        r.timestep                      = m.dt();
        r.critical_timestep             = m.dem.critical_timestep();
        r.dem_region_radius             = p.region.radius;
        r.mean_grain_diameter           = p.region.mean_diameter();
        r.grain_resolution_a_over_d     = p.tunnel_radius / p.region.mean_diameter();
        r.genesis_steps                 = m.groups.genesis_steps;
        r.genesis_reused                = m.groups.genesis_reused;
        r.genesis_wall_time_s           = m.groups.genesis_wall_time_s;
        r.interface_force_imbalance_max = m.imbalance_max();
        measures.fill(r);
        r.wall_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() +
            (r.genesis_reused ? r.genesis_wall_time_s : 0.0);
      }
    };
  } // namespace

  void check_restart(const TunnelParams &p)
  {
    if (p.restart_file.empty())
      return;
    dem::verify_checkpoint(p.restart_file); // checksums: a damaged file is refused
    const auto        md  = dem::read_checkpoint_metadata(p.restart_file);
    const std::string was = physics_text(meta_get(md, "prm", p.restart_file)),
                      now = physics_text(p.prm_text);
    if (was == now)
      return;
    // Name the first differing line of the two texts.
    std::istringstream a(was), b(now);
    std::string        la, lb;
    while (std::getline(a, la) && std::getline(b, lb) && la == lb)
      {
      }
    throw dem::InputError(
        "restart: the checkpoint " + p.restart_file +
        " was written with different parameters (its stored .prm text, after --set "
        "overrides, differs from this run's; only Problem/output directory and "
        "Output/checkpoint interval may change): first difference: '" +
        lb + "' here, '" + la + "' in the checkpoint");
  }

  TunnelResult run_tunnel(const TunnelParams &p, std::ostream &progress)
  {
    p.validate("tunnel parameters");
    if (p.dimension == 3)
      {
        TunnelWorkflow<3> workflow(p, progress);
        return workflow.run();
      }
    TunnelWorkflow<2> workflow(p, progress);
    return workflow.run();
  }
} // namespace demfem::coupling
