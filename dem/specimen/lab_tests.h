#pragma once
// Laboratory tests on a specimen built by dem/specimen/genesis.h (fistPkg §5.4-5.7):
// compression (confined / unconfined / uniaxial strain, seating then
// loading, Table 10), diametral compression (Brazilian, §5.6, Table 11,
// Eq. 22-24) and direct tension with grip grains (§5.7, Table 12), each a
// single loading stage that ends when the stress falls below a fraction of
// its peak or at a strain limit; and the properties of §5.2 (Eq. 18-20,
// docs/architecture.md, "Plane-stress and plane-strain constants"). Sign convention:
// tension positive in the history; reported strengths are magnitudes.
#include "dem/specimen/brazilian_formula.h"
#include "dem/specimen/genesis.h"
#include "dem/specimen/servo.h"

#include <array>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace demfem::dem
{
  enum class TestKind
  {
    compression,
    brazilian,
    direct_tension
  };
  /// How the crack-initiation stress is picked (docs/calibrate.md, "Crack
  /// initiation and crack damage").
  enum class CrackInitiationMethod
  {
    /// Onset of dilatancy: the crack volumetric strain (measured volumetric
    /// strain minus the elastic one of the loading branch's E, nu) leaves
    /// zero for good (Martin & Chandler 1994). Compression tests only.
    volumetric_strain,
    /// Onset of steady cracking: the crack count reaches a fraction of its
    /// value at the peak (the acoustic-emission reading).
    crack_count,
    /// Lateral strain response: where the lateral strain departs farthest
    /// from the straight line to crack damage (Nicksiar & Martin 2012); no
    /// threshold. Compression tests only.
    lateral_strain
  };

  /// Lateral boundary of a compression test (fistPkg §5.5, Table 10). All
  /// are seated at Pc (unconfined: axially only, the lateral walls
  /// removed); during loading the lateral boundary is:
  enum class CompressionType
  {
    confined,       ///< held at Pc by the servo or the pressure boundary (triaxial)
    unconfined,     ///< removed
    uniaxial_strain ///< fixed (oedometric: lateral strain held at zero)
  };

  /// One recorded step (tension positive, SI units).
  struct HistoryRow
  {
    std::int64_t step               = 0; ///< loading-phase step
    double       time               = 0; ///< loading-phase time [s]
    double       axial_strain       = 0; ///< platen/grip based (Eq. 23 for Brazilian)
    double       lateral_strain     = 0; ///< gauge based (mean of the lateral components)
    double       gauge_axial_strain = 0;
    double       volumetric_strain  = 0;    ///< gauge based (trace)
    double       axial_stress       = 0;    ///< wall (platen/grip) based [Pa]
    double       region_axial_stress   = 0; ///< measurement-region based [Pa]
    double       region_lateral_stress = 0; ///< measurement-region based [Pa]
    /// Compression with lateral walls: mean wall-based stress of the lateral
    /// walls (tension positive) [Pa]; 0 for the unconfined test.
    double      lateral_wall_stress = 0;
    double      axial_force         = 0; ///< Brazilian: Eq. 22 (tension positive) [N]
    std::size_t cracks_tension = 0, cracks_shear = 0;
    /// The loading measure the test ends on (compression: deviator
    /// magnitude; Brazilian: |F_a|; tension: axial stress) [Pa or N].
    double load = 0;
  };

  /// What a progress callback receives.
  struct LabProgress
  {
    const char  *phase         = "";
    std::int64_t step          = 0;
    double       stress        = 0; ///< current load measure (see HistoryRow::load)
    double       strain        = 0;
    std::size_t  cracks        = 0;
    double       fraction_done = 0; ///< rough: max(strain / limit, post-peak drop)
  };

  struct LabTestParams
  {
    TestKind        kind        = TestKind::compression;
    CompressionType ctype       = CompressionType::unconfined;
    double          Pc          = 0;   ///< confining pressure (compression positive) [Pa]
    double          strain_rate = 0.1; ///< axial strain rate (> 0) [1/s] (§5.4)
    double       load_fraction  = 0.7; ///< ends when load < fraction * peak (Table 10-12)
    double       strain_limit   = 0.02;    ///< ends at |axial strain| above this
    std::int64_t step_limit     = 2000000; ///< loading-phase step limit
    int          history_interval = 50;    ///< steps between history rows
    // seating (compression) / set-up (Brazilian) equilibrium
    /// Confining servo. v_limit 0: automatic, Table 10's 10 eps_rate H, in
    /// seating at most Pc / (rho c), in loading at least
    /// 2 max(Pc, |sigma_a|) / (rho c), sigma_a the axial stress of the step
    /// (docs/calibrate.md); given (> 0), the loading limit and an upper
    /// bound of the seating's automatic one; the integral gain acts in
    /// loading only.
    ServoParams servo;
    /// Confined compression, 2D: the lateral walls as flexible chains of
    /// this many facets between the platens, each vertex servo-controlled
    /// on its own (a membrane: a crack burst next to the wall moves the
    /// facets it touches, not the whole wall); 1: rigid lateral walls.
    /// Each facet at least two mean grain diameters long
    /// (docs/calibrate.md, "Confining servo").
    int lateral_segments = 1;
    /// Confined compression, 2D: from the seating on, the lateral walls
    /// give way to a pressure boundary, P_c as forces on the outermost
    /// grains (dem/specimen/pressure_boundary.h; docs/calibrate.md,
    /// "Confining boundary"); needs lateral_segments = 1.
    bool         pressure_boundary = false;
    double       ratio_limit       = 1e-4; ///< ft_eq ratio limit for seating
    std::int64_t seat_step_limit   = 100000;
    double       grip_thickness    = 0.1; ///< direct tension: t_g / H
    /// Brazilian platen friction. fistPkg §5.6 uses frictionless platens;
    /// a small 2D disk between frictionless platens can slide out sideways
    /// (neutral equilibrium), so a friction coefficient may be given.
    double platen_friction = 0;
    /// Brazilian specimen of its own (§5.6): a disk (2D) or a cylinder with
    /// its axis along y (3D) of this diameter [m], packed at the material's
    /// grain size in a box of diameter x diameter (3D: x thickness [m],
    /// default half the diameter, ISRM's t/D). 0: the disk is carved from
    /// the test vessel, radius min(W, H)/2 and the vessel's depth. A 3D
    /// disk about 11 grains across is damaged all over before it fails and
    /// does not split (docs/calibrate_ldb.md, 3D): the split needs more
    /// grains across than the compression specimen's width holds.
    double brazilian_diameter = 0, brazilian_thickness = 0;
    /// Flattened Brazilian disk: the angle 2 alpha [deg] each of the two
    /// loaded flats subtends at the disk centre (grains beyond
    /// |x_load| = R cos alpha are carved away; the flat platens then load a
    /// band 2 R sin alpha wide instead of a line one or two grains wide).
    /// 0: the round disk of fistPkg §5.6. The strength is
    /// brazilian_strength with the arc-load factor k(alpha)
    /// (docs/calibrate.md, "The flattened Brazilian disk").
    double brazilian_flat_angle = 0;
    /// Window of the modulus fit, as fractions of the peak load (loading
    /// branch before the peak): E and nu are least-squares slopes in it.
    double fit_lo = 0.1, fit_hi = 0.5;
    /// The same window in deviator stress [Pa], used instead of the
    /// fractions when fit_stress_hi > 0. The moduli of a bonded assembly
    /// depend on the stress they are read at (bonds start to break well
    /// below the peak), so a specimen compared with another material's
    /// E, nu is read at that material's stresses, not at fractions of its
    /// own peak (apps/tunnel_probe.cc; docs/tunnel.md, "The probe").
    double fit_stress_lo = 0, fit_stress_hi = 0;
    /// Crack-initiation stress reported as `crack_initiation` (both are
    /// always measured).
    CrackInitiationMethod crack_initiation_method =
        CrackInitiationMethod::volumetric_strain;
    /// Crack count method: load when the crack count first reaches this
    /// fraction of the count at peak.
    double crack_initiation_fraction = 0.01;
    /// Volumetric method: the crack volumetric strain has left zero when it
    /// stays above this fraction of the elastic volumetric strain at the
    /// peak (docs/calibrate.md: 5 % is about 5 x the gauge noise of the
    /// 1000-grain Lac du Bonnet specimen).
    double crack_volumetric_fraction = 0.05;
    /// Brazilian: the disk split when at least this fraction of its
    /// failure's cracks lie in the split zone (dem/specimen/brazilian_failure.h;
    /// 0.5: most of them, between 0.28 for cracks spread over the disk and
    /// 2/3 for a straight platen-to-platen split).
    double split_fraction = 0.5;
    /// Confined compression: P_c is held when its deviation up to the peak,
    /// averaged over a compression wave's crossing time
    /// (LabTestResult::confining_deviation_to_peak), stays within this
    /// fraction; `demfem calibrate` names a test beyond it
    /// (confinement_not_held). 1 %: the and a triaxial cell's.
    double confining_tolerance = 0.01;
    /// Time step of the test as a fraction of the critical one (0: keep the
    /// specimen's, 0.8 from its genesis). A quasi-static result does not
    /// depend on it (docs/calibrate.md, "Loading rate and time step").
    double timestep_safety = 0;

    /// Fits E and nu in the stress window the relative one (fit_lo, fit_hi)
    /// gives at a peak load `peak`: a test that ends elsewhere (a short
    /// elastic test, a region's lab specimen) measures where the test of
    /// that peak did.
    void fit_window_at(const double peak)
    {
      fit_stress_lo = fit_lo * peak;
      fit_stress_hi = fit_hi * peak;
    }

    /// Checks every field's range once where the values enter; errors name
    /// `key_prefix` + the parameter-file key (e.g. "Tests/strain rate").
    void validate(const std::string &where, int dim,
                  const std::string &key_prefix = "") const;
  };

  struct LabTestResult
  {
    TestKind                kind = TestKind::compression;
    std::vector<HistoryRow> history;
    std::int64_t            seating_steps = 0, loading_steps = 0;
    std::string             ended_by;     ///< "post-peak", "strain limit", "step limit"
    std::size_t             peak_row = 0; ///< history index of the peak
    double                  peak = 0; ///< compression: peak axial stress magnitude [Pa];
                                      ///< Brazilian: BTS (Eq. 24); tension: peak stress
    double peak_load   = 0;           ///< peak of HistoryRow::load
    double peak_force  = 0;           ///< Brazilian: F_max [N]
    double peak_strain = 0;           ///< |axial strain| at the peak
    /// Axial-stress magnitude at crack initiation by the chosen method
    /// (LabTestParams::crack_initiation_method) [Pa]; the volumetric method
    /// applies to compression (not uniaxial strain): the other tests report
    /// the crack count one.
    double crack_initiation       = 0;
    double crack_initiation_load  = 0; ///< load measure at that crack initiation
    double crack_initiation_count = 0; ///< by the crack count [Pa]
    /// By the crack volumetric strain [Pa]; NaN where it does not apply or
    /// the specimen does not dilate before the peak.
    double crack_initiation_volumetric = std::numeric_limits<double>::quiet_NaN();
    /// By the lateral strain response [Pa]; NaN where it does not apply or
    /// the volume does not reverse before the peak (no crack damage).
    double crack_initiation_lateral = std::numeric_limits<double>::quiet_NaN();
    /// Elastic constants of the loading branch (compression only):
    /// 3D: Eq. 18 (E, nu); 2D: Eq. 19 plane stress (E_ps, nu_ps) and the
    /// plane-strain pair (docs/architecture.md) in (E, nu). Uniaxial strain: E holds the
    /// constrained modulus and nu = 0.
    double      E = 0, nu = 0, E_ps = 0, nu_ps = 0;
    double      E_wall = 0; ///< modulus from platen strain (incl. contact compliance)
    std::size_t cracks_tension_peak = 0, cracks_shear_peak = 0;
    std::size_t cracks_tension = 0, cracks_shear = 0; ///< at the end
    /// Cracks of the loading phase by what broke (index: BondType), at the
    /// end: material cracks (contact / parallel bond, flat joint) apart
    /// from joint cracks (smooth joint).
    std::array<std::size_t, n_bond_types> cracks_by_type{};
    /// Confined compression (Pc > 0): largest relative deviation
    /// |P_a - Pc| / Pc of the servo-controlled lateral wall pressures P_a,
    /// each averaged over windows of `confining_window` (the time a
    /// compression wave takes to cross the specimen between the confining
    /// walls), over every step of the loading phase (to the end, past the
    /// peak) and up to the peak; NaN for the other tests.
    double confining_deviation         = std::numeric_limits<double>::quiet_NaN();
    double confining_deviation_to_peak = std::numeric_limits<double>::quiet_NaN();
    /// The largest single-step deviation up to the peak (a crack burst next
    /// to a wall kicks its contact forces for a few steps), and the
    /// averaging window [s].
    double confining_spike_to_peak = std::numeric_limits<double>::quiet_NaN();
    double confining_window        = std::numeric_limits<double>::quiet_NaN();
    /// The loading servo's wall velocity limit [m/s] at the peak step
    /// (Tests/servo velocity limit, or the automatic one, which grows with
    /// the axial stress); NaN for the other tests.
    double confining_velocity_limit = std::numeric_limits<double>::quiet_NaN();
    /// Facets of each lateral wall between the platens (1: rigid walls; 0
    /// for the other tests).
    int lateral_wall_segments = 0;
    /// Confined compression: "rigid walls", "flexible walls" or "pressure"
    /// (LabTestParams::pressure_boundary); empty for the other tests.
    std::string confining_boundary;
    /// Crack-damage stress (Martin & Chandler): axial-stress magnitude at the
    /// reversal of the volumetric strain (gauge based), i.e. at the most
    /// compacted state before the peak; NaN if the volume only grows.
    double crack_damage = std::numeric_limits<double>::quiet_NaN();
    /// Peak stress in the measurement regions (fistPkg §5.7), magnitude:
    /// direct tension: largest region-averaged axial tension over the
    /// loading; compression: region axial stress at the peak row; NaN for
    /// the Brazilian test (its stress field is not uniform).
    double peak_region = std::numeric_limits<double>::quiet_NaN();
    /// Brazilian failure mode (dem/specimen/brazilian_failure.h): "split",
    /// "not_split" (the BTS is no tensile strength) or "no_failure" (no
    /// crack after the peak); empty for the other tests. Decided by the
    /// fraction `split_fraction` of the failure's `failure_cracks` cracks
    /// (the last ones, brazilian_failure_cracks) in the split zone.
    std::string failure_mode;
    double      split_fraction = std::numeric_limits<double>::quiet_NaN();
    std::size_t failure_cracks = 0;
    /// Fraction of all the loading phase's cracks in the split zone at the
    /// peak row and at the end (NaN: no cracks, or not a Brazilian test).
    double split_fraction_peak = std::numeric_limits<double>::quiet_NaN();
    double split_fraction_end  = std::numeric_limits<double>::quiet_NaN();
    double R = 0, t = 0; ///< Brazilian disk radius and thickness [m]
    double area = 0;     ///< cross-section used for the axial stress [m^2]
  };

  /// Callbacks: progress (every history row) and state snapshots, called
  /// with label "peak" at every row that sets a new peak and "end" once.
  template <int dim>
  struct LabCallbacks
  {
    std::function<void(const LabProgress &)>                        progress;
    std::function<void(const Specimen<dim> &, const std::string &)> snapshot;
  };

  /// Runs one test on `s` (modified: carved, walls moved, bonds broken).
  template <int dim>
  LabTestResult run_lab_test(Specimen<dim> &s, const LabTestParams &p,
                             const LabCallbacks<dim> &cb = {});

  /// Plane-stress (Eq. 19) to plane-strain constants for the continuum
  /// (docs/architecture.md, "Plane-stress and plane-strain constants"): nu = nu'/(1 +
  /// nu'), E = E' (1 - nu^2).
  inline void plane_stress_to_plane_strain(double E_ps, double nu_ps, double &E,
                                           double &nu)
  {
    nu = nu_ps / (1 + nu_ps);
    E  = E_ps * (1 - nu * nu);
  }

  /// The vessel a Brazilian specimen is packed in: `v` itself when the
  /// disk is carved from the test vessel (brazilian_diameter 0), else a box
  /// of brazilian_diameter across (3D: brazilian_thickness deep, default
  /// half the diameter). The grain size is the material's either way.
  VesselParams brazilian_vessel(const VesselParams &v, const LabTestParams &p, int dim);
  /// True when the Brazilian test has a specimen of its own.
  inline bool own_brazilian_specimen(const LabTestParams &p)
  {
    return p.brazilian_diameter > 0;
  }

  /// Least-squares slope of y(x) over the points (both of equal size >= 2).
  double ls_slope(const std::vector<double> &x, const std::vector<double> &y);

  const char *test_kind_name(TestKind k);

  /// The parameter-file name of a crack-initiation method ("volumetric
  /// strain", "crack count", "lateral strain") and back; the parse throws
  /// naming the allowed names.
  const char           *crack_initiation_method_name(CrackInitiationMethod m);
  CrackInitiationMethod parse_crack_initiation_method(const std::string &name);
  /// The Patterns::Selection text of the names above.
  inline constexpr const char *crack_initiation_method_names =
      "volumetric strain|crack count|lateral strain";
} // namespace demfem::dem
