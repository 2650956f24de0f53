#pragma once
// What a `demfem tunnel` run produced and whether it reached what it was
// asked (docs/tunnel.md, "Run status and exit codes"; docs/architecture.md,
// "Outputs and run status"). No deal.II here: the study, the summary writer
// and the tests read results without the continuum's headers.
#include "coupling/damage_zone.h"
#include "coupling/initiation_zone.h"
#include "dem/engine/types.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace demfem::coupling
{
  /// A phase ends at equilibrium when the continuum's kinetic energy is down
  /// to this fraction of its peak in the phase (with the DEM's unbalanced
  /// ratio and the interface residual below Coupling/equilibrium ratio).
  inline constexpr double kinetic_energy_target = 1e-4;

  /// One cycling phase of the workflow (in-situ, each excavation stage,
  /// final equilibrium) as it ended.
  struct PhaseRecord
  {
    std::string  name;
    std::int64_t steps      = 0;
    double       time_start = 0, time_end = 0; ///< model time [s]
    double       timestep = 0;                 ///< at the phase end [s]
    /// The DEM's unbalanced-force ratio, the continuum's kinetic energy over
    /// its peak in the phase and the interface residual, at the phase end.
    double unbalanced_ratio = 0, kinetic_energy_ratio = 0, interface_residual = 0;
    /// Ended by the equilibrium criterion, not by its step limit.
    bool equilibrated = false;
    /// The continuum's kinetic-energy peak the criterion measured against
    /// [J] (the phase's own, or the one it continues: tunnel_phase.h).
    double kinetic_energy_peak = 0;
    /// Where the wall time went [s] (summary.json "phase_costs"; not part of
    /// the results: a restarted phase counts from the restart): the whole
    /// phase, the continuum steps, the DEM steps, gathering the interface
    /// forces, the equilibrium criterion, outputs (history, VTK,
    /// checkpoints).
    double wall_time_s = 0, continuum_s = 0, dem_s = 0, interface_s = 0, criterion_s = 0,
           output_s = 0;
  };

  /// Whether a phase that did not equilibrate was stopped by the physical
  /// limit `time_limit` (Coupling/phase time limit; 0: none) rather than by
  /// its step limit.
  inline bool ended_at_time_limit(const PhaseRecord &ph, double time_limit)
  {
    return time_limit > 0 && ph.time_end - ph.time_start >= time_limit * (1 - 1e-12);
  }

  /// summary.json "status", most severe first. Exit codes:
  /// docs/tunnel.md, "Run status and exit codes".
  enum class RunStatus
  {
    ok,
    diverged,            ///< instability (energy, kinetic-energy growth, NaN)
    time_not_advancing,  ///< dt lost in round-off of t: no physical time passed
    in_situ_not_reached, ///< region stress before excavation not sigma0
    not_equilibrated,    ///< a phase ended at its step limit
    region_too_small,    ///< the damage zone reached the coupling boundary
  };
  std::string status_name(RunStatus s);
  /// Throws std::invalid_argument for an unknown name.
  RunStatus status_from_name(const std::string &name);
  int       exit_code(RunStatus s);

  struct TunnelResult
  {
    RunStatus status   = RunStatus::ok;
    bool      diverged = false;
    /// Every failed check, most severe first, each with its numbers.
    std::vector<std::pair<RunStatus, std::string>> problems;
    std::string                                    diagnosis; ///< of a divergence
    std::vector<PhaseRecord>                       phases;

    int          dimension = 2;
    std::string  variant, scheme, embedding; ///< embedding: "" (2D), slab, section
    double       slab_thickness = 0, axial_extension = 0;
    std::size_t  n_particles = 0, n_contacts = 0, n_fem_dofs = 0;
    std::int64_t steps = 0, packing_steps = 0;
    double       timestep = 0, critical_timestep = 0; ///< coupled dt, DEM critical
    /// The in-situ ramp: its duration [s], the region's crossing time it is
    /// measured in [s] (RegionParams::crossing_time) and its steps at dt.
    double                 ramp_duration = 0, ramp_crossing_time = 0;
    std::int64_t           ramp_steps   = 0;
    double                 wall_time_s  = 0;
    std::size_t            cracks_total = 0, cracks_tensile = 0, cracks_shear = 0;
    nlohmann::ordered_json cracks_by_type;
    std::size_t            cracks_before_excavation = 0;
    /// Excavation cracks within two mean diameters of the coupling boundary:
    /// all, and those of the damage zone (connected to the wall). The zone's
    /// make the region too small (the continuum cannot crack: the region
    /// cuts the zone).
    std::size_t cracks_near_interface      = 0;
    std::size_t zone_cracks_near_interface = 0;
    bool        region_too_small           = false;
    double      dem_region_radius          = 0;
    /// 90th-percentile crack distance of the zone connected to the wall [m]
    double     damage_zone_depth     = 0;
    double     damage_zone_depth_max = 0; ///< largest crack distance, all cracks [m]
    DamageZone damage; ///< the excavation's damage zone (summary "damage")
    /// The excavation cracks against the elastic zones of the material's
    /// crack-initiation stresses (summary "elastic_initiation_zones";
    /// empty without a material file or before the excavation).
    std::vector<InitiationZone> initiation_zones;
    double      wall_convergence_mean = 0; ///< mean inward radial displacement [m]
    double      interface_force_imbalance_max = 0;
    std::size_t n_wall_particles              = 0;
    /// Reference (x, y) of the wall grains that wall_convergence_mean
    /// averages (for a closed form evaluated where they are; docs/study.md).
    std::vector<std::array<double, 2>> wall_points;
    /// sigma0 asked (in plane) and the centre-disk stress measured before the
    /// excavation; in_situ_error = max |difference| / max |sigma0 principal|.
    Eigen::Matrix2d sigma0 = Eigen::Matrix2d::Zero();
    Eigen::Matrix2d region_stress_before =
        Eigen::Matrix2d::Zero();        ///< centre disk, pre-excavation (in plane)
    double region_stress_before_zz = 0; ///< 3D: szz of the same region
    double in_situ_error           = 0;
    double in_situ_tolerance       = 0;
    /// The in-situ servo (coupling/in_situ_servo.h; summary "in_situ_servo"):
    /// its tolerance (0: off or not available), the error at each
    /// measurement, whether it converged, the final interface strain, its
    /// size relative to the in-situ strain and the region's fitted in-plane
    /// stiffness over the continuum's {lambda + mu, mu}.
    struct Servo
    {
      double                tolerance = 0;
      std::vector<double>   errors;
      bool                  converged        = false;
      Eigen::Matrix2d       interface_strain = Eigen::Matrix2d::Zero();
      double                relative_strain  = 0;
      std::array<double, 2> stiffness_ratios{{1, 1}};
    } servo;
    double phase_time_limit    = 0; ///< Coupling/phase time limit [s] (0: none)
    double ratio_tolerance     = 0;
    double mean_grain_diameter = 0;
    /// Tunnel radius over the region's mean grain diameter (a/d): below 10
    /// the damage zone is a few grains deep (warned at the start).
    double grain_resolution_a_over_d = 0;
    /// Steps of the material genesis the region was carved from (not in
    /// `steps` or `packing_steps`: its own model; coupling/region_genesis.cc).
    std::int64_t genesis_steps = 0;
    /// The genesis packing was reused from an earlier run in this process
    /// (coupling/genesis_cache.h); genesis_wall_time_s is its wall time,
    /// paid by this run or by the earlier one. wall_time_s is the run's
    /// cost on its own: a reused packing's wall time is counted in it, so
    /// that runs of a sweep compare on the same basis.
    bool   genesis_reused      = false;
    double genesis_wall_time_s = 0;
    /// Stopped on request (signal): a checkpoint was written, no summary.
    bool                     interrupted = false;
    std::string              checkpoint;   ///< latest checkpoint written ("" none)
    std::vector<dem::Vec<2>> positions;    ///< final grain positions (model order), 2D
    std::vector<dem::Vec<3>> positions_3d; ///< same, 3D
  };

  /// The in-situ servo's interface strain over the in-situ strain beyond
  /// which the in-situ state counts as not reached (InSituServo::
  /// contrast_limit, coupling/in_situ_servo.h).
  inline constexpr double servo_contrast_limit = 0.5;

  /// in_situ_error of a stress: max |stress - sigma0| over the in-plane
  /// components, relative to the largest |sigma0 principal| (0 for sigma0 =
  /// 0): the measure of Tunnel/in situ tolerance and of the in-situ servo.
  double in_situ_error(const Eigen::Matrix2d &stress, const Eigen::Matrix2d &sigma0);

  /// The outcome checks (DESIGN "Run status"; docs/tunnel.md): fills
  /// status and problems from the phases, the in-situ stress, the cracks at
  /// the boundary and a divergence already recorded. A run that diverged is
  /// not checked further (its state is not an answer).
  void assess_outcome(TunnelResult &r);

  /// summary.json of a finished (not interrupted) run.
  nlohmann::ordered_json summary_json(const TunnelResult &r);

  /// PhaseRecords as text lines for a checkpoint, and back.
  std::string              phases_to_text(const std::vector<PhaseRecord> &phases);
  std::vector<PhaseRecord> phases_from_text(const std::string &text);
} // namespace demfem::coupling
