#pragma once
// One cycling phase of the tunnel workflow (in-situ installation, an
// excavation stage, the final equilibrium; docs/tunnel.md, "Phase limits"):
// the coupled model is stepped until equilibrium or a limit, with the
// workflow's outputs and checkpoints at step boundaries. The phase ends at
// equilibrium when
//   - the DEM's unbalanced-force ratio is below the ratio tolerance,
//   - the continuum's kinetic energy is down to kinetic_energy_target of its
//     peak in the phase (tunnel_result.h),
//   - the interface residual (quasi-static: |u* - u| / |u*|; condensed: the
//     interface force residual, coupling_scheme.h) is below the tolerance,
//     measured over at least two windows of `subcycles` steps of this phase
//     (not while the in-situ servo holds the continuum: the held continuum
//     is not iterated, its residual is the servo's remaining error),
//   - and no grain is held on the in-situ installation's path;
// checked every 100 steps. It ends unequilibrated at its step limit (the
// cost budget) or its model-time limit (physical). The returned PhaseRecord
// says which, and where the wall time went.
#include "coupling/coupled_model.h"
#include "coupling/tunnel_result.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

namespace demfem::coupling
{
  /// When a phase ends (docs/tunnel.md, "Phase limits").
  struct PhaseLimits
  {
    std::int64_t min_steps       = 0; ///< no equilibrium before (e.g. the ramp)
    std::int64_t step_limit      = 0; ///< Coupling/step limit (+ ramp)
    double       time_limit      = 0; ///< Coupling/phase time limit [s]; 0: none
    double       ratio_tolerance = 1e-3;
  };

  /// Where a phase is: the iteration about to run, the continuum's kinetic
  /// energy peak so far and the model time at the phase start. Stored with
  /// checkpoints, so that a phase resumes exactly where it stopped.
  struct PhaseProgress
  {
    std::int64_t iteration           = 1;
    double       kinetic_energy_peak = 0;
    double       time_start          = 0;
  };

  /// Runs phase `name` from `at` (resumed: the first iteration's boundary is
  /// the checkpoint itself and is not repeated); a fresh phase measures the
  /// continuum's kinetic energy against `continued_peak` at least (the peak
  /// of the phase it continues; 0: its own peak only). `load(n)` sets the load
  /// factor before iteration n. The hooks (class Hooks):
  ///   at_boundary(progress)  before an iteration (checkpoint, interruption);
  ///   output(step)           after each step (history rows, VTK frames);
  ///   progress_line(ratio)   every 2000 iterations and at the end;
  /// at_boundary and output return the wall time they spent writing [s]
  /// (booked as output; nothing is timed on steps that write nothing).
  template <int dim, class Load, class Hooks>
  PhaseRecord run_phase(CoupledModel<dim> &m, const std::string &name,
                        const PhaseLimits &limits, PhaseProgress at, bool resumed,
                        double continued_peak, Load &&load, Hooks &hooks)
  {
    using clock      = std::chrono::steady_clock;
    const auto since = [](clock::time_point t) {
      return std::chrono::duration<double>(clock::now() - t).count();
    };
    if (!resumed)
      at = PhaseProgress{1, continued_peak, m.dem.time()};
    const std::int64_t n0          = at.iteration;
    const auto         wall0       = clock::now();
    const auto         times0      = m.step_times();
    double             criterion_s = 0, output_s = 0;
    bool               equilibrated = false;
    std::int64_t       n_end        = n0 - 1;
    // A sub-cycled or quasi-static interface is judged over two windows of
    // this phase at least (else the residual of the previous phase's last
    // window ended excavation stages early: measured convergence 0.0037 m
    // instead of 0.0086 m with subcycles = 800).
    const std::int64_t windows = 2 * m.coupling_params().subcycles;
    for (at.iteration = n0; at.iteration <= limits.step_limit; ++at.iteration)
      {
        const std::int64_t n = at.iteration;
        if (!(resumed && n == n0)) // the checkpoint we resumed from
          output_s += hooks.at_boundary(at);
        load(n);
        m.step();
        n_end = n;
        if (limits.time_limit > 0 && m.dem.time() - at.time_start >= limits.time_limit)
          break; // the physical limit (equilibrated stays false)
        output_s += hooks.output(m.dem.step_count());
        if (n % 100 == 0)
          {
            const auto   tc        = clock::now();
            const double ke        = m.continuum_kinetic_energy();
            at.kinetic_energy_peak = std::max(at.kinetic_energy_peak, ke);
            const double ur        = m.dem.unbalanced_ratio();
            if (!std::isfinite(ur) || !std::isfinite(ke))
              throw dem::InstabilityError(
                  "non-finite unbalanced force or continuum energy at step " +
                  std::to_string(m.dem.step_count()) +
                  ": the run diverged (time step too large?)");
            if (n % 2000 == 0)
              hooks.progress_line(ur);
            // While grains are held on the installation path, the unbalanced
            // ratio and the (kinematic) continuum's kinetic energy are both
            // zero: not an equilibrium.
            equilibrated =
                !m.installing() && n >= std::max(limits.min_steps, windows) &&
                ur < limits.ratio_tolerance &&
                ke <= kinetic_energy_target * at.kinetic_energy_peak &&
                (m.continuum_held() || m.interface_residual() < limits.ratio_tolerance);
            criterion_s += since(tc);
            if (equilibrated)
              break;
          }
      }
    hooks.progress_line(m.dem.unbalanced_ratio());
    PhaseRecord ph;
    ph.name             = name;
    ph.steps            = n_end;
    ph.time_start       = at.time_start;
    ph.time_end         = m.dem.time();
    ph.timestep         = m.dt();
    ph.unbalanced_ratio = m.dem.unbalanced_ratio();
    const double ke     = m.continuum_kinetic_energy();
    ph.kinetic_energy_ratio =
        at.kinetic_energy_peak > 0 ? ke / at.kinetic_energy_peak : 0.0;
    ph.interface_residual  = m.interface_residual();
    ph.equilibrated        = equilibrated;
    ph.kinetic_energy_peak = at.kinetic_energy_peak;
    const auto &times      = m.step_times();
    ph.wall_time_s         = since(wall0);
    ph.continuum_s         = times.continuum - times0.continuum;
    ph.dem_s               = times.dem - times0.dem;
    ph.interface_s         = times.interface - times0.interface;
    ph.criterion_s         = criterion_s;
    ph.output_s            = output_s;
    return ph;
  }
} // namespace demfem::coupling
