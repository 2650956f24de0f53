#pragma once
// Settings shared by the parts of `demfem calibrate` (calibrate_command.cc
// reads and validates them; calibrate_run.cc runs the genesis and the tests).
#include "dem/laws/smooth_joint_law.h"
#include "dem/specimen/genesis.h"
#include "dem/specimen/lab_tests.h"

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace demfem::apps
{
  /// Peaks deviating more than this when the loading rate is halved flag a
  /// test as not quasi-static (fistPkg §5.4 asks for a rate-independent
  /// peak; 2 % is well above the peak's own step-to-step resolution). With
  /// Problem/seeds > 1 the seed means are judged against it as well.
  inline constexpr double calibrate_rate_tolerance = 0.02;

  /// A test of Tests/tests and what it runs.
  struct TestSpec
  {
    std::string          name;
    dem::TestKind        kind;
    dem::CompressionType ctype;
  };

  /// A target of the automatic fit (subsection Fit/Targets): the measured
  /// seed mean should lie within `tolerance` (relative) of `value`.
  struct FitTarget
  {
    std::string name; ///< E, nu, ucs, bts, direct tension, crack initiation ratio, mi
    double      value = 0, weight = 1, tolerance = 0.05;
  };

  /// A searched microparameter (Fit/parameters) and its bounds.
  struct FitParameter
  {
    std::string name; ///< a Material key, e.g. "effective modulus"
    double      lo = 0, hi = 0;
  };

  /// Seed mean and sample standard deviation of each measured target.
  struct FitMeasurement
  {
    std::map<std::string, double> mean, sd;
    std::string                   error; ///< non-empty: the evaluation failed
    /// What the means leave out (e.g. a Brazilian disk that did not split),
    /// logged in fit.csv and on the progress line.
    std::string note;
  };

  /// One evaluation of an earlier fit, a row of its fit.csv (Fit/resume
  /// from): replayed instead of measured again when the search asks for
  /// the same parameters in the same order.
  struct FitLogRow
  {
    std::string         stage;
    std::vector<double> values; ///< every Fit/parameters entry
    FitMeasurement      measured;
    double              seconds = 0; ///< what it cost then
  };

  /// `demfem calibrate FILE.prm --fit`: searches the parameters with a
  /// derivative-free optimizer (NLopt) for the targets (docs/calibrate.md,
  /// "Automatic calibration").
  struct FitSettings
  {
    bool                      enabled = false;
    std::vector<FitTarget>    targets;
    std::vector<FitParameter> parameters;
    int                       seeds       = 3;  ///< packings averaged per evaluation
    int                       evaluations = 60; ///< budget per stage
    std::string               algorithm   = "bobyqa";
    double elastic_strain                 = 3e-4; ///< axial strain of the elastic stage
    /// Fit/brazilian seeds: disks the BTS target is averaged over (seeds
    /// seed, seed+1, ...; 0: Fit/seeds). Those beyond Fit/seeds run the
    /// Brazilian test only: a coarse 3D disk's BTS scatters far more than
    /// the UCS or the direct tension of its packing (docs/calibrate_ldb.md).
    int brazilian_seeds = 0;
    /// Fit/resume from: an earlier fit.csv of the same parameters and
    /// targets, read when the settings are (before the output directory is
    /// claimed); its evaluations are replayed in order.
    std::string            resume_from;
    std::vector<FitLogRow> replay;

    int brazilian_disks() const { return brazilian_seeds > 0 ? brazilian_seeds : seeds; }
  };

  struct CalibrateSettings
  {
    int                   dim = 2;
    std::string           out, where;
    bool                  vtk = true;
    dem::MaterialParams   mat;
    dem::VesselParams     vessel;
    double                n_grains = 0;
    std::vector<TestSpec> tests;
    dem::LabTestParams    lab;
    /// Slower repeats of each test (fistPkg §5.4): 0 none, 1 at half rate,
    /// 2 at half and at quarter rate.
    int rate_check = 0;
    /// Tests/confining pressures: one test each in the triaxial series [Pa].
    std::vector<double> confining_pressures;
    /// Smooth-jointed interface (fistPkg §2.8): plane through joint_point
    /// with the orientation and properties of joint_sj (3D uses all three
    /// coordinates, 2D the first two).
    bool                           joint = false;
    std::array<double, 3>          joint_point{{0, 0, 0}};
    dem::SmoothJointLaw<3>::Params joint_sj;
    FitSettings                    fit;
    /// Problem/seeds: packings the tests run on (run_calibration_seeds).
    int seeds = 1;
    /// Put after "demfem calibrate: " in this run's messages and in its
    /// tests' progress lines: the packing ("seed 10001: ") when packings run
    /// side by side, empty otherwise.
    std::string log_tag;
  };

  /// A copy of a specimen whose model state is in `checkpoint` (written by
  /// dem::write_checkpoint from `s`): the same law groups, the state bit for
  /// bit, so every test starts from the same packing without repeating it.
  template <int dim>
  std::unique_ptr<dem::Specimen<dim>> clone_specimen(const dem::Specimen<dim> &s,
                                                     const std::string &checkpoint);

  /// The member of `m` a Fit/parameters name searches; std::invalid_argument
  /// naming `where` and the allowed names for an unknown one.
  double &fit_parameter(dem::MaterialParams &m, const std::string &name,
                        const std::string &where);

  /// How a calibration ended: the exit code and the status the manifest
  /// records ("ok", "step_limit_reached", "brazilian_not_split",
  /// "confinement_not_held", "targets_not_reached"; exit 3 for any failure,
  /// docs/calibrate.md).
  struct CalibrateOutcome
  {
    int         exit_code = 0;
    std::string status    = "ok";
  };

  /// The status of a calibration in which `n_at_step_limit` tests ended at
  /// their step limit, `n_not_split` Brazilian disks did not split and
  /// `n_not_held` confined tests did not hold P_c within
  /// Tests/confining tolerance: "ok" when all are zero, else
  /// step_limit_reached (a test stopped early may not have failed yet, so
  /// it is named first), else brazilian_not_split (a strength missing),
  /// else confinement_not_held (a strength at another confinement).
  std::string calibration_status(std::size_t n_at_step_limit, std::size_t n_not_split,
                                 std::size_t n_not_held = 0);

  /// The end of a calibration whose material.json and summary.json are in
  /// `out`: reports where they are after `wall_s` seconds, and exit 3 with
  /// calibration_status when it is not "ok" (apps/calibrate_output.cc).
  CalibrateOutcome calibration_outcome(const std::string &out, double wall_s,
                                       std::size_t n_at_step_limit,
                                       std::size_t n_not_split = 0,
                                       std::size_t n_not_held  = 0);

  /// Runs the automatic fit, then the calibration of the best material
  /// (run_calibration): that run's outcome when it failed, else
  /// targets_not_reached when a target stayed outside its tolerance.
  template <int dim>
  CalibrateOutcome run_fit(const CalibrateSettings &s);

  /// Runs the calibration (creates the output directory): step_limit_reached
  /// when a test ended at its step limit.
  template <int dim>
  CalibrateOutcome run_calibration(const CalibrateSettings &s);

  /// Problem/seeds > 1: run_calibration on each packing seed (Material/seed,
  /// + 1, ...) into seed_<n>/, then material.json in s.out with the seed
  /// means of every measured property, `seed_scatter` (sample standard
  /// deviations), `seed_values` and `seeds` (apps/calibrate_seeds.cc). The
  /// outcome is the first failed seed's, else ok. seeds = 1: run_calibration.
  template <int dim>
  CalibrateOutcome run_calibration_seeds(const CalibrateSettings &s);
} // namespace demfem::apps
