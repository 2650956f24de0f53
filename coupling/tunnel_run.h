#pragma once
// The `demfem tunnel` workflow (issue 5) on the wall-facet coupled model:
// build, in-situ stress ramp and equilibrium, excavation (at once or in
// stages with the removed grains' forces relaxed to zero), cycling to
// equilibrium; cracks, wall convergence, damage-zone depth, interface
// force balance and energies; summary.json, history.csv,
// wall_displacement.csv and VTK series (.pvd per series and a combined one).
#include "coupling/wall_facet_model.h"

#include <cstdint>
#include <ostream>
#include <string>

namespace demfem::coupling
{
  struct TunnelParams
  {
    std::string     output_directory = "out/tunnel";
    double          tunnel_radius    = 1.0;
    Eigen::Matrix2d sigma0 = (Eigen::Matrix2d() << -30e6, 0, 0, -60e6).finished();
    int             stages = 1; ///< excavation stages
    RegionParams    region;
    ContinuumParams continuum;
    CouplingParams  coupling;
    double          ratio_tolerance  = 1e-3; ///< equilibrium: unbalanced ratio below this
    std::int64_t    ramp_steps       = 2000; ///< in-situ load ramp
    std::int64_t    phase_step_limit = 20000; ///< per equilibrium phase / stage
    std::int64_t vtk_interval = 1000; ///< steps between VTK frames (0: phase ends only)
    std::int64_t history_interval = 100;
    bool         write_vtk        = true;

    /// Checks the geometry (tunnel inside the region by >= 3 grains, region
    /// inside the continuum) and every sub-parameter; throws dem::InputError.
    void validate(const std::string &where) const;
  };

  struct TunnelResult
  {
    bool            diverged = false;
    std::string     diagnosis;
    std::size_t     n_particles = 0, n_contacts = 0, n_fem_dofs = 0;
    std::int64_t    steps        = 0;
    double          wall_time_s  = 0;
    std::size_t     cracks_total = 0, cracks_tensile = 0, cracks_shear = 0;
    double          damage_zone_depth     = 0;
    double          wall_convergence_mean = 0; ///< mean inward radial displacement [m]
    double          interface_force_imbalance_max = 0;
    std::size_t     n_wall_particles              = 0;
    Eigen::Matrix2d region_stress_before =
        Eigen::Matrix2d::Zero(); ///< centre disk, pre-excavation
    double mean_grain_diameter = 0;
  };

  /// Runs the workflow; writes into p.output_directory (created here, after
  /// validation). Divergence does not throw: it is reported in the result
  /// (and summary.json) with a diagnosis; no non-finite number is written.
  TunnelResult run_tunnel(const TunnelParams &p, std::ostream &progress);
} // namespace demfem::coupling
