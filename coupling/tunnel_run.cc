#include "coupling/tunnel_run.h"

#include "coupling/excavation_measures.h"
#include "coupling/tunnel_frames.h"
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
    if (!(continuum.outer_radius > 2 * region.radius))
      throw dem::InputError(w + ": DEM region/radius (" + std::to_string(region.radius) +
                            " m) must be smaller than half of Continuum/outer radius (" +
                            std::to_string(continuum.outer_radius) + " m)");
    dem::check_range(w, "Continuum/young modulus", continuum.young_modulus, 0, inf, true);
    dem::check_range(w, "Continuum/poisson ratio", continuum.poisson_ratio, -1, 0.5, true,
                     true);
    dem::check_range(w, "Tunnel/excavation stages", stages, 1, 1000);
    dem::check_range(w, "Continuum/axial extension", continuum.axial_extension, 0, inf);
    if (dimension == 2 && continuum.axial_extension > 0)
      throw dem::InputError(w + ": Continuum/axial extension = " +
                            std::to_string(continuum.axial_extension) +
                            " m is for Problem/dimension = 3 (a tunnel section in a 3D "
                            "continuum); allowed in 2D: 0");
    coupling.validate(w);
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
    std::string num(double x)
    {
      if (!std::isfinite(x))
        return "null";
      std::ostringstream s;
      s << std::setprecision(10) << x;
      return s.str();
    }

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

    // The continuum of a tunnel section (3D) has the tunnel through it.
    ContinuumParams with_tunnel(const TunnelParams &p)
    {
      ContinuumParams c = p.continuum;
      c.tunnel_radius   = p.tunnel_radius;
      return c;
    }

    template <int dim>
    struct Runner
    {
      const TunnelParams                &p;
      std::ostream                      &out;
      std::unique_ptr<CoupledModel<dim>> model;
      CoupledModel<dim>                 &m;
      std::string                        dir;
      // history.csv is kept here and written whole (temporary file + rename)
      // at every frame, checkpoint and at the end: a kill leaves the last
      // complete file, never a torn row.
      std::ostringstream history;
      TunnelFrames<dim>  frames{dir}; // after dir: initialized from it
      // Positions and removed grains' forces by id at the excavation, and the
      // cracks before it (coupling/excavation_measures.h).
      excavation::Record<dim>               exc;
      bool                                  excavated = false;
      std::string                           phase     = "build";
      std::chrono::steady_clock::time_point t0        = std::chrono::steady_clock::now();
      std::int64_t budget = 0; // expected coupled steps for the ETA (upper bound)
      std::int64_t step0  = 0; // steps of the packing
      // Checkpoint / restart state (docs/architecture.md, "Checkpoints and restart"):
      // the workflow position is the phase index (0 in-situ, 1..stages excavation
      // stage, stages+1 equilibrium, stages+2 done) and the iteration n of its cycle
      // loop.
      int                             phase_index = 0;
      bool                            resuming    = false;
      std::int64_t                    resume_n    = 1;
      double                          resume_peak = 0;
      double                          phase_t0    = 0; // model time at the phase start
      std::vector<PhaseRecord>        phases;          // the phases ended so far
      Eigen::Matrix<double, dim, dim> stress_before =
          Eigen::Matrix<double, dim, dim>::Zero();
      std::string last_checkpoint;

      Runner(const TunnelParams &pp, std::ostream &o)
          : p(pp)
          , out(o)
          , model(make_coupled_model<dim>(pp.region, with_tunnel(pp), pp.coupling,
                                          MPI_COMM_WORLD))
          , m(*model)
          , dir(pp.output_directory)
      {
      }

      static std::string history_header()
      {
        return std::string(
                   "step,time,phase,load_factor,unbalanced_ratio,dem_kinetic_energy,"
                   "dem_strain_energy,continuum_kinetic_energy,cracks,cracks_tensile,"
                   "cracks_shear,interface_force_imbalance,wall_convergence_mean,"
                   "ring_force_x,ring_force_y,interface_residual") +
               (dim == 3 ? ",ring_force_z" : "") + ",damage_zone_depth\n";
      }

      void save_history()
      {
        dem::vtkout::write_text_atomically(dir + "/history.csv", history.str());
      }

      std::size_t cracks(int mode) const { return excavation::count_cracks(m.dem, mode); }

      // Mean inward radial displacement of the grains within one mean
      // diameter of the wall since excavation started (excavation_measures.h).
      double convergence(std::size_t                        *n    = nullptr,
                         std::vector<std::array<double, 6>> *rows = nullptr) const
      {
        return excavated ? excavation::wall_convergence(m.dem, exc.ref, p.tunnel_radius,
                                                        p.region.mean_diameter(), n, rows)
                         : 0.0;
      }

      // Excavation cracks within two mean grain diameters of the coupling
      // ring: the excavation's damage reached the boundary, where the
      // continuum cannot crack (status region_too_small). Cracks of the
      // in-situ phase are not the excavation's and are counted apart.
      std::size_t near_interface() const
      {
        if (!excavated)
          return 0;
        std::size_t  n  = 0;
        const double r0 = m.continuum_inner_radius() - 2 * p.region.mean_diameter();
        for (std::size_t k = exc.cracks_before; k < m.dem.cracks.size(); ++k)
          n += m.dem.cracks[k].position.template head<2>().norm() > r0;
        return n;
      }

      void write_frame()
      {
        save_history();
        if (p.write_vtk)
          frames.write(m);
      }

      void record()
      {
        const auto  &D   = m.dem;
        const double ur  = D.unbalanced_ratio();
        const double kef = m.continuum_kinetic_energy();
        const auto   F   = m.interface_force();
        history << D.step_count() << "," << num(D.time()) << "," << phase << ","
                << num(m.get_load_factor()) << "," << num(ur) << ","
                << num(D.kinetic_energy()) << "," << num(D.strain_energy()) << ","
                << num(kef) << "," << cracks(-1) << "," << cracks(0) << "," << cracks(1)
                << "," << num(m.imbalance_last()) << "," << num(convergence()) << ","
                << num(F[0]) << "," << num(F[1]) << "," << num(m.interface_residual());
        if constexpr (dim == 3)
          history << "," << num(F[dim - 1]);
        // The damage zone as it grows, stage by stage (excavation cracks).
        history << ","
                << num(excavated ? excavation::damage_zone_depth(m.dem, exc.cracks_before,
                                                                 p.tunnel_radius)
                                 : 0.0)
                << "\n";
      }

      void progress_line(double ur)
      {
        const double el =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const auto   n   = m.dem.step_count() - step0;
        const double eta = n > 0 ? el / n * std::max<std::int64_t>(0, budget - n) : 0;
        out << "[" << phase << "] step " << n << "  t = " << std::setprecision(4)
            << m.dem.time() << " s  ratio = " << ur << "  cracks = " << cracks(-1)
            << "  ETA <= " << std::setprecision(3) << eta << " s" << std::endl;
        // Damage reaching the coupling boundary means the region is too small
        // for the scene: the continuum cannot crack (docs/architecture.md,
        // "Speed-versus-accuracy study").
        if (!warned_region_too_small && near_interface() > 0)
          {
            warned_region_too_small = true;
            out << "warning: excavation cracks within two grain diameters of the "
                   "coupling "
                   "boundary "
                   "(r > "
                << m.continuum_inner_radius() - 2 * p.region.mean_diameter()
                << " m): the DEM region is too small for this damage; enlarge DEM "
                   "region/radius or use 'auto'"
                << std::endl;
          }
      }
      bool warned_region_too_small = false;

      // Cycles until equilibrium (DEM ratio below tolerance and the
      // continuum's kinetic energy down to kinetic_energy_target of its peak)
      // or `limit` steps; `load` sets the load factor per step.
      template <class Load>
      void cycle(std::int64_t min_steps, std::int64_t limit, Load load)
      {
        double       ke_peak = 0;
        std::int64_t n0      = 1;
        const bool   resumed = resuming;
        if (resuming)
          {
            n0       = resume_n;
            ke_peak  = resume_peak;
            resuming = false;
          }
        else
          phase_t0 = m.dem.time();
        bool         equilibrated = false;
        std::int64_t n_end        = n0 - 1;
        // Where the wall time goes (PhaseRecord costs; docs/study.md).
        using clock            = std::chrono::steady_clock;
        const auto wall0       = clock::now();
        const auto times0      = m.step_times();
        double     criterion_s = 0, output_s = 0;
        const auto since = [](clock::time_point t) {
          return std::chrono::duration<double>(clock::now() - t).count();
        };
        for (std::int64_t n = n0; n <= limit; ++n)
          {
            // Step boundary: the state is "about to run iteration n".
            if (!(resumed && n == n0)) // the checkpoint we resumed from
              {
                const auto s0 = m.dem.step_count();
                const bool stop =
                    tunnel_stop_requested != 0 || s0 - step0 == p.stop_at_step;
                if (stop || (p.checkpoint_interval > 0 && n > 1 &&
                             s0 % p.checkpoint_interval == 0))
                  {
                    const auto t = clock::now();
                    checkpoint(n, ke_peak);
                    output_s += since(t);
                  }
                if (stop)
                  {
                    out << "demfem tunnel: interrupted at step " << s0
                        << "; checkpoint written to " << last_checkpoint << std::endl;
                    throw Interrupted{};
                  }
              }
            load(n);
            m.step();
            n_end = n;
            if (p.phase_time_limit > 0 && m.dem.time() - phase_t0 >= p.phase_time_limit)
              break; // the physical limit (equilibrated stays false)
            const auto s = m.dem.step_count();
            if (s % p.history_interval == 0 ||
                (p.vtk_interval > 0 && s % p.vtk_interval == 0))
              {
                const auto t = clock::now();
                if (s % p.history_interval == 0)
                  record();
                if (p.vtk_interval > 0 && s % p.vtk_interval == 0)
                  write_frame();
                output_s += since(t);
              }
            if (n % 100 == 0)
              {
                const auto   tc = clock::now();
                const double ke = m.continuum_kinetic_energy();
                ke_peak         = std::max(ke_peak, ke);
                const double ur = m.dem.unbalanced_ratio();
                if (!std::isfinite(ur) || !std::isfinite(ke))
                  throw dem::InstabilityError(
                      "non-finite unbalanced force or continuum energy at step " +
                      std::to_string(s) + ": the run diverged (time step too large?)");
                if (n % 2000 == 0)
                  progress_line(ur);
                // Quasi-static: no continuum inertia (ke = 0); the interface
                // residual |u* - u| / |u*| must be down to the tolerance too,
                // measured in this phase: two windows of `subcycles` steps at
                // least (else the residual of the previous phase's last
                // window ended excavation stages early: measured convergence
                // 0.0037 m instead of 0.0086 m with subcycles = 800).
                const std::int64_t windows = 2 * p.coupling.subcycles;
                // While grains are held on the installation path, the
                // unbalanced ratio and the (kinematic) continuum's kinetic
                // energy are both zero: not an equilibrium.
                equilibrated = !m.installing() && n >= std::max(min_steps, windows) &&
                               ur < p.ratio_tolerance &&
                               ke <= kinetic_energy_target * ke_peak &&
                               m.interface_residual() < p.ratio_tolerance;
                criterion_s += since(tc);
                if (equilibrated)
                  break;
              }
          }
        progress_line(m.dem.unbalanced_ratio());
        PhaseRecord ph;
        ph.name                 = phase;
        ph.steps                = n_end;
        ph.time_start           = phase_t0;
        ph.time_end             = m.dem.time();
        ph.timestep             = m.dt();
        ph.unbalanced_ratio     = m.dem.unbalanced_ratio();
        const double ke         = m.continuum_kinetic_energy();
        ph.kinetic_energy_ratio = ke_peak > 0 ? ke / ke_peak : 0.0;
        ph.interface_residual   = m.interface_residual();
        ph.equilibrated         = equilibrated;
        const auto &times       = m.step_times();
        ph.wall_time_s          = since(wall0);
        ph.continuum_s          = times.continuum - times0.continuum;
        ph.dem_s                = times.dem - times0.dem;
        ph.interface_s          = times.interface - times0.interface;
        ph.criterion_s          = criterion_s;
        ph.output_s             = output_s;
        phases.push_back(ph);
        if (!equilibrated)
          out << "warning: phase '" << phase << "' ended at its "
              << (ended_at_time_limit(ph, p.phase_time_limit) ? "time limit ("
                                                              : "step limit (")
              << n_end << " steps, " << ph.time_end - ph.time_start
              << " s) before equilibrium: unbalanced ratio " << ph.unbalanced_ratio
              << " (target " << p.ratio_tolerance << ")" << std::endl;
      }

      // The workflow's numbers in a checkpoint (dem/io/state_archive.h): one
      // function for saving and loading. `step`: the DEM step of the
      // checkpoint (history.csv is trimmed to it on restart).
      void serialize(dem::StateArchive &ar, std::int64_t &n, double &ke_peak,
                     std::int64_t &step)
      {
        ar.io("run.phase_index", phase_index);
        ar.io("run.iteration", n);
        ar.io("run.step", step);
        ar.io("run.kinetic_energy_peak", ke_peak);
        ar.io("run.phase_start_time", phase_t0);
        ar.io("run.excavated", excavated);
        ar.io("run.cracks_before_excavation", exc.cracks_before);
        ar.io("run.positions_at_excavation", exc.ref);
        ar.io("run.removed_grain_forces", exc.removed_forces);
        ar.io("run.region_stress_before", stress_before);
      }

      void checkpoint(std::int64_t n, double ke_peak)
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
        serialize(ar, n, ke_peak, step);
        save_history();
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
        serialize(ar, resume_n, resume_peak, step);
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
        // history.csv: the rows up to the checkpoint's step, from this
        // directory's file when it continues the run, else from the file next
        // to the checkpoint (a restart into a new directory gets the whole
        // history, header included).
        std::filesystem::path source(dir + "/history.csv");
        if (!std::filesystem::exists(source))
          source = std::filesystem::absolute(file).parent_path() / "history.csv";
        std::ifstream in(source);
        std::string   l;
        history.str("");
        history << history_header();
        for (bool first = true; std::getline(in, l); first = false)
          {
            if (first && l + "\n" == history_header())
              continue;
            const auto comma = l.find(',');
            char      *end   = nullptr;
            const auto row_step =
                std::strtoll(l.c_str(), &end, 10); // our own rows: "step,..."
            if (comma != std::string::npos && end == l.c_str() + comma &&
                row_step <= step)
              history << l << "\n";
          }
        save_history();
        out << "demfem tunnel: restarted from " << file << " at step " << step << " ("
            << phase << ")" << std::endl;
      }

      void excavate(int start)
      {
        if (start == 0)
          {
            exc       = excavation::remove_tunnel_grains(m.dem, p.tunnel_radius);
            excavated = true;
          }
        for (int s = std::max(1, start); s <= p.stages; ++s)
          {
            phase_index = s;
            phase = "excavation " + std::to_string(s) + "/" + std::to_string(p.stages);
            const double rem = 1.0 - double(s) / p.stages;
            // A section's continuum tunnel wall is released with the grains.
            m.set_excavation_release(rem);
            if (!resuming) // a resumed stage has its loads in the checkpoint
              {
                excavation::apply_removed_forces(m.dem, exc, rem);
                m.dem.reset_energy_baseline();
              }
            cycle(200, p.phase_step_limit, [](std::int64_t) {});
            write_frame();
          }
      }

      TunnelResult run()
      {
        TunnelResult r;
        check_restart(p); // a foreign checkpoint: refused before anything is written
        std::filesystem::create_directories(dir);
        out << "demfem tunnel: building the DEM region and the continuum" << std::endl;
        m.build(&out);
        m.set_insitu(p.sigma0);
        r.n_fem_dofs = m.n_fem_dofs();
        budget       = p.ramp_steps + p.phase_step_limit * (2 + p.stages);
        step0        = m.dem.step_count();
        if (!p.restart_file.empty())
          restore(p.restart_file);
        else
          {
            history << history_header();
            write_frame();
          }
        const int start = phase_index;
        try
          {
            if (start == 0)
              {
                phase = "in-situ";
                cycle(p.ramp_steps, p.ramp_steps + p.phase_step_limit,
                      [&](std::int64_t n) {
                        m.set_load_factor(std::min(1.0, double(n) / p.ramp_steps));
                      });
                if constexpr (dim == 2)
                  stress_before =
                      region_stress(m.dem, Vec<2>::Zero(), 0.5 * p.region.radius);
                else if (m.section()) // the free core between the end layers
                  stress_before = region_stress(
                      m.dem, Vec<3>::Zero(), 0.5 * p.region.radius, m.end_overlap(),
                      p.region.slab_thickness - m.end_overlap());
                else
                  stress_before =
                      region_stress(m.dem, Vec<3>::Zero(), 0.5 * p.region.radius,
                                    p.region.slab_thickness);
                write_frame();
              }
            if (start <= p.stages)
              excavate(start);
            if (start <= p.stages + 1)
              {
                phase_index = p.stages + 1;
                phase       = "equilibrium";
                cycle(0, p.phase_step_limit, [](std::int64_t) {});
              }
            phase_index = p.stages + 2;
          }
        catch (const Interrupted &)
          {
            save_history();
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
        if (!r.diverged)
          {
            write_frame();
            if (p.checkpoint_interval > 0) // final state, e.g. to continue
              checkpoint(0, 0);
          }
        save_history();
        fill_result(r);
        if (!r.diverged)
          {
            std::vector<std::array<double, 6>> rows;
            convergence(nullptr, &rows);
            std::ostringstream w;
            w << "x,y,z,ux,uy,uz\n" << std::setprecision(12);
            for (const auto &q : rows)
              w << q[0] << "," << q[1] << "," << q[2] << "," << q[3] << "," << q[4] << ","
                << q[5] << "\n";
            dem::vtkout::write_text_atomically(dir + "/wall_displacement.csv", w.str());
          }
        assess_outcome(r);
        dem::vtkout::write_text_atomically(dir + "/summary.json",
                                           summary_json(r).dump(2) + "\n");
        return r;
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
        r.sigma0                  = p.sigma0;
        r.region_stress_before    = stress_before.template topLeftCorner<2, 2>();
        r.region_stress_before_zz = dim == 3 ? stress_before(dim - 1, dim - 1) : 0.0;
        r.in_situ_tolerance       = p.in_situ_tolerance;
        r.phase_time_limit        = p.phase_time_limit;
        r.ratio_tolerance         = p.ratio_tolerance;
        r.phases                  = phases;
        r.checkpoint              = last_checkpoint;
        if constexpr (dim == 2)
          r.positions = m.dem.particles.x;
        else
          r.positions_3d = m.dem.particles.x;
        r.n_particles              = m.dem.particles.size();
        r.n_contacts               = m.dem.n_contacts();
        r.steps                    = m.dem.step_count();
        r.packing_steps            = step0;
        r.timestep                 = m.dt();
        r.critical_timestep        = m.dem.critical_timestep();
        r.cracks_total             = cracks(-1);
        r.cracks_tensile           = cracks(0);
        r.cracks_shear             = cracks(1);
        r.cracks_by_type           = excavation::cracks_by_type(m.dem);
        r.cracks_before_excavation = exc.cracks_before;
        r.cracks_near_interface    = near_interface();
        r.region_too_small         = r.cracks_near_interface > 0;
        r.dem_region_radius        = p.region.radius;
        r.mean_grain_diameter      = p.region.mean_diameter();
        r.damage = excavation::damage_zone(m.dem, exc.cracks_before, p.tunnel_radius);
        r.damage_zone_depth             = r.damage.depth;
        r.damage_zone_depth_max         = r.damage.depth_max;
        r.interface_force_imbalance_max = m.imbalance_max();
        r.wall_convergence_mean         = convergence(&r.n_wall_particles);
        r.wall_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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
        Runner<3> runner(p, progress);
        return runner.run();
      }
    Runner<2> runner(p, progress);
    return runner.run();
  }
} // namespace demfem::coupling
