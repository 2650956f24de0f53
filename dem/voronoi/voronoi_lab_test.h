#pragma once
// Laboratory tests on rigid or flexible Voronoi grains (docs/voronoi.md,
// "Lab tests"; seed 004 §2): a rectangular specimen packed by the DEM genesis
// (dem/specimen/genesis.h), tessellated (Laguerre cells clipped to the
// vessel's inner box), loaded by rigid platens at a strain rate given in
// physical terms (1/s): unconfined compression (frictional platens),
// confined compression (pressure Pc on the boundary edges, then the
// platens add the deviator), direct tension (glued platens); and the
// Brazilian test on a disk specimen between flat platens.
//
// Measures (the conventions of dem/specimen/lab_tests.h: tension positive
// in the history, strengths reported as magnitudes):
//  - axial stress from the platen reaction, mean of the two platens over
//    W t, minus the confining pressure for the confined test (Brazilian:
//    the strength F / (pi R t));
//  - axial strain from the platens' displacement over H; lateral strain
//    from the mean displacement of the grains (rigid: their centres;
//    flexible: the ends of their side edges) on the left and right sides
//    over their distance (both since the start of the axial loading);
//  - E and nu of the 2D specimen (sigma_xx = 0 at the sides, so plane
//    stress of the rigid-body-spring network; for nu = 0 plane stress and
//    plane strain coincide): least-squares slopes of the load and of minus
//    the lateral strain against the axial strain over the history rows of
//    the loading branch whose load is within [fit_lo, fit_hi] of the peak.
#include "dem/voronoi/flexible_model.h"
#include "dem/voronoi/rigid_model.h"
#include "dem/voronoi/tessellation.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace demfem::dem::voronoi
{
  /// Specimen geometry and packing (the DEM genesis with a linear material:
  /// grain-scaling packing at a low material pressure).
  struct VoronoiSpecimenParams
  {
    double        width    = 0.025; ///< W (x) [m]
    double        height   = 0.05;  ///< H (y, the loading axis) [m]
    double        d_min    = 1.0;   ///< disk diameters uniform in [d_min, d_max]
    double        d_max    = 1.66;  ///<   before the scaling to n_grains [m]
    double        n_grains = 300;   ///< about this many grains (diameter multiplier)
    std::uint64_t seed     = 10000;
    double        packing_pressure = 1e5;  ///< genesis material pressure [Pa]
    double        packing_modulus  = 1e10; ///< E* of the packing contacts [Pa]
  };

  /// A tessellated packing.
  struct VoronoiSpecimen
  {
    std::vector<double> x, y, radius; ///< disks
    ClipDomain          domain;       ///< rectangle (or circle)
    Tessellation        tessellation;
  };

  /// Packs disks with dem::build_specimen and tessellates them, clipped to
  /// the vessel's inner box. Throws InputError for bad parameters.
  VoronoiSpecimen make_voronoi_specimen(const VoronoiSpecimenParams &p);

  /// A disk specimen for the Brazilian test: the packing of
  /// make_voronoi_specimen (set width = height = D), its disks whose
  /// centres lie inside the inscribed circle, tessellated clipped to that
  /// circle (a regular polygon of `sides`).
  VoronoiSpecimen make_voronoi_disk_specimen(const VoronoiSpecimenParams &p,
                                             int                          sides = 256);

  enum class VoronoiTest
  {
    unconfined_compression,
    confined_compression,
    direct_tension,
    brazilian ///< disk specimen (make_voronoi_disk_specimen)
  };

  struct VoronoiLabParams
  {
    VoronoiTest  test               = VoronoiTest::unconfined_compression;
    double       confining_pressure = 0;    ///< Pc (compression positive) [Pa]
    double       strain_rate        = 1.0;  ///< axial strain rate (> 0) [1/s]
    double       load_fraction      = 0.7;  ///< ends when the load < fraction * peak
    double       strain_limit       = 0.01; ///< ends at |axial strain| above this
    std::int64_t step_limit         = 2000000;
    double       safety             = 0.5; ///< time step = safety * stable estimate
    double       damping            = 0.7; ///< local non-viscous damping alpha
    /// Compression and Brazilian platens (0: no end friction; a small 2D
    /// disk between frictionless platens can slide out sideways, so give
    /// the Brazilian test some, e.g. 0.5).
    double platen_friction = 0;
    /// Brazilian: the platens' points are on the outline within this angle
    /// of the poles [deg] (the contact arc stays far smaller).
    double      disk_platen_cone = 30;
    PointScheme scheme           = PointScheme::lobatto3;
    /// Flexible grains: the mesh (merging of short cell edges).
    FlexibleMeshOptions flexible_mesh;
    /// History rows every this axial-strain increment (a physical interval,
    /// so the rows do not depend on the time step).
    double history_strain = 2e-6;
    /// Window of the E, nu fit, fractions of the peak load (loading branch).
    double fit_lo = 0.1, fit_hi = 0.5;
    /// Confined test: the confining phase ends when the unbalanced-force
    /// ratio (sum |F| of the grains / sum |F| of the contact points) is
    /// below this, or after confining_step_limit steps.
    double       ratio_limit          = 1e-4;
    std::int64_t confining_step_limit = 200000;

    void validate(const std::string &where) const;
  };

  /// One history row (tension positive).
  struct VoronoiLabRow
  {
    std::int64_t step           = 0; ///< loading-phase step
    double       time           = 0; ///< loading-phase time [s]
    double       axial_strain   = 0;
    double       lateral_strain = 0;
    /// Platen stress minus Pc (Brazilian: -F / (2 R t)) [Pa].
    double axial_stress = 0;
    /// What the test ends on [Pa]: deviator (compression), axial stress
    /// (tension), F / (pi R t) (Brazilian).
    double load           = 0;
    int    cracks_tensile = 0, cracks_shear = 0;
  };

  enum class VoronoiLabStatus
  {
    ok,                 ///< ended after the peak or at the strain limit
    step_limit_reached, ///< the step limit came first
  };

  struct VoronoiLabResult
  {
    VoronoiLabStatus           status = VoronoiLabStatus::ok;
    std::string                ended_by; ///< "post-peak", "strain limit", "step limit"
    std::vector<VoronoiLabRow> history;
    /// |axial stress| at the peak (confined: Pc + deviator; Brazilian: the
    /// BTS F_max / (pi R t)) [Pa].
    double       peak_stress = 0;
    double       peak_load   = 0; ///< peak of the load (confined: the deviator) [Pa]
    double       peak_strain = 0; ///< |axial strain| at the peak
    double       peak_force = 0; ///< Brazilian: F_max [N] (peak_stress: F_max / (pi R t))
    double       E          = 0; ///< 2D modulus of the loading branch [Pa]
    double       nu         = 0; ///< -d(lateral) / d(axial) strain
    int          cracks_tensile_peak = 0, cracks_shear_peak = 0; ///< at the peak row
    int          cracks_tensile = 0, cracks_shear = 0;           ///< at the end
    std::int64_t confining_steps = 0, loading_steps = 0;
    double       time_step = 0; ///< at the start of the test [s]
    /// At the end: lowered when contacts formed during the test [s].
    double final_time_step = 0;
    int    new_contacts    = 0; ///< contacts formed during the test
    int    n_grains = 0, n_contacts = 0, n_points = 0;
  };

  /// Runs one test on a fresh rigid model of `specimen` (contact material
  /// `contact`, grain density rho). `final_model`, if given, receives the
  /// model at the end (for VTK output).
  VoronoiLabResult run_voronoi_lab_test(
      const VoronoiSpecimen &specimen, const ContactMaterial &contact, double density,
      const VoronoiLabParams           &params,
      std::optional<RigidVoronoiModel> *final_model = nullptr);

  /// The same test with flexible grains (dem/voronoi/flexible_model.h) of
  /// elasticity `grain` (its density and thickness; the thickness must be
  /// the contact's), meshed with params.flexible_mesh. The lateral gauge is
  /// the ends of the side edges (over their distance, about W). The
  /// Brazilian test as the rigid one, the disk platens' points carried by
  /// the nodes.
  VoronoiLabResult run_flexible_voronoi_lab_test(
      const VoronoiSpecimen &specimen, const ContactMaterial &contact,
      const GrainElasticity &grain, const VoronoiLabParams &params,
      std::optional<FlexibleVoronoiModel> *final_model = nullptr);

  /// Cracked grain-contact points by mode (tensile, shear).
  void count_cracks(const RigidVoronoiContacts &contacts, int &tensile, int &shear);

  /// Seconds per grain-step of the rigid model (contacts, platen-free) on a
  /// jittered hexagonal lattice of about n_grains polydisperse disks (about
  /// three contacts per grain, as a dense packing), `steps` steps, with the
  /// current OpenMP thread count (parallel from 4096 grains / 8192
  /// contacts). For the benchmark; no genesis (it would dominate at 1e5
  /// grains). `time_step`, if given, receives the step used (0.5 of the
  /// stable estimate) [s].
  double voronoi_cost_per_grain_step(int n_grains, int steps = 200,
                                     std::uint64_t seed = 1, double *time_step = nullptr);

  /// The same for flexible grains (grain E 70 GPa, nu 0.25, the default
  /// short-edge merging) on the same lattice: the cost per grain-step and,
  /// in `time_step`, the step (smaller than the rigid one: the elements and
  /// the node masses bound it).
  double flexible_voronoi_cost_per_grain_step(int n_grains, int steps = 200,
                                              std::uint64_t seed      = 1,
                                              double       *time_step = nullptr);
} // namespace demfem::dem::voronoi
