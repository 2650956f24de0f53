#pragma once
// Full-DEM reference of the breakable tunnel (docs/architecture.md,
// "Speed-versus-accuracy study"): the whole
// domain r <= R (R >= 8 a) as bonded DEM, no continuum, with the in-situ
// stress held at the outer boundary by a servo-controlled flexible membrane;
// the same excavation workflow and the same damage bookkeeping as the
// embedded tunnel (coupling/excavation_measures.h), so that `demfem study`
// can compare the embedded model's damage-zone depth and crack counts with
// it and tabulate the speed-up.
//
// Why a membrane (and not a box with dem/servo walls): the region is packed
// and bonded by coupling::build_disk_region, the procedure of the embedded
// region, which packs a disk inside a closed ring of facets; a box would
// need another packing (another material). The ring's vertices are
// servo-controlled individually: vertex j is driven so that the force the
// grains exert on it equals F_j = sum over its two facets e of
// (sigma0 n_e) L_e / 2 (n_e outward, tension positive: a compressive sigma0
// pushes the grains inward, the grains push the vertex outward). This
// carries the full anisotropic traction sigma0.n (normal and shear), which
// a pair of axis-aligned servo walls cannot on a circle. The half-facet
// lumping is exact for the boundary's average stress:
// sum_j F_j (x) x_j = -sigma0 A (A the polygon area), hence the held stress
// is measured as sigma_b = -(1/A) sum_j sym(f_j (x) x_j), f_j the measured
// vertex forces (the Love average of the body's stress for a
// traction-free tunnel wall).
//
// Servo law per vertex (fistPkg §5.3, Itasca 2008 §3.10.5, vector form):
// v_j = alpha (f_j - lambda F_j) / (k_j dt), k_j the normal stiffness of
// the grain-facet contacts on it weighted by their barycentric weights
// (floor: one grain-wall contact, 2 E*), the step limited to max_step.
#include "coupling/damage_zone.h"
#include "coupling/dem_region.h"
#include "coupling/initiation_zone.h"
#include "coupling/tunnel_result.h"

#include <Eigen/Dense>

#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace demfem::coupling
{
  struct MembraneServoParams
  {
    double alpha     = 0.5;  ///< gain, (0, 1]
    double tolerance = 0.02; ///< held stress: |sigma_b - sigma0|_F <= tol |sigma0|_F
    double max_step  = 1e-3; ///< largest vertex move per step / mean grain diameter
  };

  /// The servo-controlled membrane: a closed ring of facets (one wall) whose
  /// vertices follow the servo law above. 3D (the plane-strain slab
  /// 0 < z < t between the region's fixed frictionless walls): the wall is
  /// the lateral cylinder of triangles (add_cylinder_ring); each triangle
  /// lumps a third of its traction force (sigma0 n) A on each vertex, the
  /// vertices move in the xy plane only, and the held stress is
  /// sigma_b = -(1/V) sum_j sym(f_j (x) x_j) over the xy components, V the
  /// enclosed volume. The lumping is exact there too: over the lateral
  /// surface, sum_e n_e A_e (x) c_e = V I in the xy block (divergence
  /// theorem; the planes z = 0, t contribute only to the z row).
  template <int dim>
  class MembraneServo
  {
  public:
    /// `wall`: the membrane's wall id in m.walls (2D: vertices in ring order).
    MembraneServo(const dem::Model<dim> &m, int wall, const MembraneServoParams &p,
                  double mean_diameter, double contact_stiffness_floor);
    /// Target stress (in-plane, tension positive); the load factor scales it.
    void set_target(const Eigen::Matrix2d &sigma0) { target = sigma0; }
    /// Sets the vertex velocities from the forces of the last step; call
    /// after every Model::step (and once before the first).
    void update(dem::Model<dim> &m, double load_factor) const;
    /// Target vertex forces (force the grains exert on each vertex, in the
    /// order of vertices()) for the current geometry, scaled by the load
    /// factor.
    std::vector<dem::Vec<dim>> target_forces(const dem::Model<dim> &m,
                                             double                 load_factor) const;
    /// Held in-plane stress sigma_b (tension positive).
    Eigen::Matrix2d held_stress(const dem::Model<dim> &m) const;
    /// |sigma_b - lambda sigma0|_F / |sigma0|_F.
    double relative_error(const dem::Model<dim> &m, double load_factor) const;
    /// Enclosed polygon area (2D, signed: > 0 counter-clockwise) or volume (3D).
    double                  enclosed(const dem::Model<dim> &m) const;
    const std::vector<int> &vertices() const { return ring; }

  private:
    std::vector<int> ring;   // vertex indices (2D: in ring order)
    std::vector<int> facets; // 3D: the wall's facets
    std::vector<int> slot;   // 3D: position in `ring` of each vertex id (-1: not on it)
    std::vector<std::vector<int>> columns; // 3D: positions in `ring` above one another
    MembraneServoParams           p;
    double                        d = 0, k_floor = 0;
    Eigen::Matrix2d               target = Eigen::Matrix2d::Zero();
  };

  struct FullDemReferenceParams
  {
    /// 2: the disk r <= R of disks. 3: the slab 0 < z < t of the cylinder
    /// r <= R of spheres (t = region.slab_thickness), between fixed
    /// frictionless walls (plane strain, as the embedded slab and the
    /// section's far field), the membrane on its lateral surface.
    int             dimension        = 2;
    std::string     output_directory = "out/reference";
    double          tunnel_radius    = 1.0;
    Eigen::Matrix2d sigma0 = (Eigen::Matrix2d() << -30e6, 0, 0, -60e6).finished();
    int             stages = 1; ///< excavation stages
    /// The material and packing of the embedded region; region.radius is
    /// the outer radius R of the DEM domain.
    RegionParams region;
    double       min_radius_factor = 8; ///< R >= this x a (boundary far from damage)
    /// Bonds whose contact point lies within this many mean grain diameters
    /// of the membrane (in-plane radius > R - band d) are unbreakable: the
    /// membrane is the loading frame, not rock (measured in 3D: 783 bonds
    /// there broke at the in-situ stress, all within two grains of it, none
    /// inside; 2D: 3-10). 0: breakable to the membrane. At most R / (4 d).
    double boundary_band = 3;
    /// The damage zone's link length in mean grain diameters (as the
    /// embedded run's Tunnel/damage link length: both measured alike).
    double damage_link_diameters = DamageZone::default_link_grain_diameters;
    /// The material's crack-initiation stresses [Pa] by material.json key
    /// and, in 3D, the Poisson ratio of the plane-strain sigma_zz: the
    /// excavation cracks are compared with their elastic zones as in the
    /// embedded run (coupling/initiation_zone.h; empty: no comparison).
    std::vector<std::pair<std::string, double>> crack_initiation;
    double                                      poisson_ratio = 0.25;
    double safety          = 0.8; ///< dt = safety x DEM critical
    double ratio_tolerance = 1e-3;
    /// The in-situ ramp's duration in crossing times of the reference
    /// region, 2 R / sqrt(E* / rho) (RegionParams::crossing_time, R the
    /// reference radius): physical, as the embedded run's.
    double              ramp_crossing_times = 4;
    std::int64_t        phase_step_limit    = 20000;
    std::int64_t        history_interval    = 100;
    MembraneServoParams servo;

    /// Throws dem::InputError naming the key (prefixed by `where`).
    void validate(const std::string &where) const;
  };

  struct FullDemReferenceResult
  {
    bool         diverged = false;
    std::string  diagnosis;
    std::size_t  n_particles = 0, n_contacts = 0, n_membrane_vertices = 0;
    std::int64_t steps = 0, packing_steps = 0;
    /// Steps of the material genesis the disk (slab) was carved from, in its
    /// own model (coupling/region_genesis.cc); packing_steps are the
    /// region model's steps before the in-situ phase (none: the carved
    /// region is finalized without cycling).
    std::int64_t genesis_steps = 0;
    double       wall_time_s = 0, timestep = 0;
    std::size_t  cracks_total = 0, cracks_tensile = 0, cracks_shear = 0;
    std::size_t  cracks_before_excavation = 0, cracks_near_boundary = 0;
    /// The damage zone (coupling/damage_zone.h) of the excavation cracks
    /// within the evaluation radius R/2; damage_zone_depth is the
    /// 90th-percentile depth of its zone connected to the wall (beyond R/2, the membrane
    /// and the in-situ cracks it causes influence the result: measured, a crack 2.26 m
    /// from the wall at r = 0.83 R, at a spot cracked during the in-situ ramp, broken by
    /// the excavation's unloading wave); the 90th percentile of all excavation cracks at
    /// any radius (damage_zone_depth_all) and the count of those beyond R/2.
    DamageZone damage;
    /// The same cracks against the elastic crack-initiation zones.
    std::vector<InitiationZone> initiation_zones;
    double                      damage_zone_depth = 0;
    double      damage_zone_depth_max    = 0; ///< largest crack distance (r <= R/2)
    double      damage_zone_depth_all    = 0;
    std::size_t cracks_beyond_evaluation = 0;
    std::size_t unbreakable_band_bonds   = 0; ///< bonds made unbreakable (boundary_band)
    double      slab_thickness           = 0; ///< 3D: t [m]
    double      evaluation_radius        = 0;
    double      wall_convergence_mean    = 0; ///< mean inward radial displacement [m]
    std::size_t n_wall_particles         = 0;
    /// In-situ state before excavation: stress held by the membrane, its
    /// relative error, whether within the servo tolerance, and the
    /// Love-Weber stress of the grains in the disk r < R/2 (3D: the
    /// cylinder r < R/2 through the slab; its in-plane block): an
    /// independent check of the servo.
    Eigen::Matrix2d held_stress_insitu   = Eigen::Matrix2d::Zero();
    double          servo_error_insitu   = -1;
    bool            servo_held_insitu    = false;
    Eigen::Matrix2d region_stress_insitu = Eigen::Matrix2d::Zero();
    double          servo_error_final    = -1; ///< at the end of the run
    double          final_ratio          = -1;
    bool            equilibrated = false; ///< every phase ended below the tolerances
    /// summary.json "status", most severe first: diverged, in_situ_not_reached
    /// (the membrane did not hold sigma0 within the servo tolerance before the
    /// excavation), not_equilibrated (a phase ended at its step limit), ok.
    RunStatus status = RunStatus::ok;
  };

  /// Runs the reference; writes summary.json, history.csv and
  /// wall_displacement.csv into p.output_directory. Divergence does not
  /// throw (result.diverged, with the engine's diagnosis); bad parameters
  /// throw dem::InputError before anything is written.
  FullDemReferenceResult run_full_dem_reference(const FullDemReferenceParams &p,
                                                std::ostream                 &progress);
} // namespace demfem::coupling
