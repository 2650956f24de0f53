#pragma once
// The `demfem tunnel` workflow on the coupled model (either
// variant, coupled_model.h; 2D or the 3D plane-strain slab):
// build, in-situ stress ramp and equilibrium, excavation (at once or in
// stages with the removed grains' forces relaxed to zero), cycling to
// equilibrium; cracks, wall convergence, damage-zone depth, interface
// force balance and energies; summary.json, history.csv,
// wall_displacement.csv and VTK series (.pvd per series and a combined one).
#include "coupling/coupled_model.h"
#include "coupling/tunnel_result.h"

#include <csignal>
#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace demfem::coupling
{
  struct TunnelParams
  {
    std::string output_directory = "out/tunnel";
    /// 2: plane strain; 3: the slab 0 < z < region.slab_thickness of the
    /// same problem (plane strain through walls, coupled_model.h).
    int             dimension     = 2;
    double          tunnel_radius = 1.0;
    Eigen::Matrix2d sigma0        = (Eigen::Matrix2d() << -30e6, 0, 0, -60e6).finished();
    int             stages        = 1; ///< excavation stages
    RegionParams    region;
    ContinuumParams continuum;
    CouplingParams  coupling;
    double          ratio_tolerance = 1e-3; ///< equilibrium: unbalanced ratio below this
    /// In-situ state reached: centre-disk stress before excavation within
    /// this fraction of the largest |sigma0 principal| (tunnel_result.h).
    double in_situ_tolerance = 0.02;
    /// In-situ servo (coupling/in_situ_servo.h): the region's centre-disk
    /// stress is corrected to within this fraction of sigma0 (same measure)
    /// before the continuum is released; 0: off (the kinematic
    /// installation alone). Only where the interface follows the affine
    /// path (CoupledModel::follows_affine_path); < in_situ_tolerance.
    double in_situ_servo_tolerance = 0.005;
    /// The damage zone's link length L in mean grain diameters of the
    /// region (coupling/damage_zone.h; Tunnel/damage link length).
    double damage_link_diameters = DamageZone::default_link_grain_diameters;
    /// The material file's crack-initiation stresses [Pa] by key
    /// ("crack_initiation", "crack_initiation_crack_count"): the excavation
    /// cracks are compared with the elastic zones where sigma1 - sigma3
    /// reaches them (coupling/initiation_zone.h); empty: no comparison.
    std::vector<std::pair<std::string, double>> crack_initiation;
    /// Duration of the in-situ load ramp in crossing times of the region
    /// (RegionParams::crossing_time, 2 R / sqrt(E* / rho)): a physical
    /// time, the same for every time step (Coupling/ramp crossing times).
    double       ramp_crossing_times = 4;
    std::int64_t phase_step_limit    = 20000; ///< per equilibrium phase / stage
    /// Model time an equilibrium phase / stage may take [s] (0: no limit):
    /// the physical limit, independent of the time step; the step limit
    /// is the cost budget.
    double       phase_time_limit = 0;
    std::int64_t vtk_interval = 1000; ///< steps between VTK frames (0: phase ends only)
    std::int64_t history_interval = 100;
    bool         write_vtk        = true;
    /// Steps between checkpoints (output_directory/checkpoint.h5, written
    /// atomically; also written at the end of the run); 0: none
    /// (docs/architecture.md, "Checkpoints and restart").
    std::int64_t checkpoint_interval = 0;
    /// Checkpoint to continue from ("" : fresh run). It must have been
    /// written with the same prm_text (output directory and checkpoint
    /// interval excepted), else dem::InputError names it.
    std::string restart_file;
    /// The full parameter text after overrides, stored in checkpoints.
    std::string prm_text;
    /// Testing aid: behave as if interrupted (SIGINT) after this many
    /// coupled steps (packing steps not counted; -1: never).
    std::int64_t stop_at_step = -1;

    /// Checks the geometry (tunnel inside the region by >= 3 grains, region
    /// inside the continuum) and every sub-parameter; throws dem::InputError.
    void validate(const std::string &where) const;
  };

  /// Set by a SIGINT/SIGTERM handler (nothing else is async-signal-safe):
  /// the run writes a checkpoint at the next step boundary and returns with
  /// TunnelResult::interrupted.
  extern volatile std::sig_atomic_t tunnel_stop_requested;

  /// Refuses (dem::InputError naming the file) a restart checkpoint written
  /// with other physics parameters, or damaged; nothing when p.restart_file
  /// is empty. run_tunnel calls it too; a caller may call it earlier, before
  /// claiming the output directory.
  void check_restart(const TunnelParams &p);

  /// Runs the workflow; writes into p.output_directory (created here, after
  /// validation). Divergence does not throw: it is reported in the result
  /// (and summary.json) with a diagnosis; no non-finite number is written.
  /// The result's status is set by assess_outcome (tunnel_result.h).
  TunnelResult run_tunnel(const TunnelParams &p, std::ostream &progress);
} // namespace demfem::coupling
