#pragma once
// The search of `demfem calibrate FILE.prm --fit` (docs/calibrate.md,
// "Automatic calibration"), independent of the material family: a
// derivative-free optimizer from NLopt searches the listed microparameters,
// normalised to [0, 1] within their bounds, for the targets. The family
// (bonded disks in calibrate_fit.cc, Voronoi grains in
// calibrate_voronoi_fit.cc) says which parameters are elastic and measures a
// parameter set: it packs Fit/seeds specimens and averages their test
// results, so the objective is a deterministic function of the parameters.
#include "apps/calibrate.h"
#include "dem/specimen/target_front.h"

#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace demfem::apps
{
  /// Reads subsection Fit (the caller has entered it): the seeds, budget,
  /// algorithm, searched parameters and targets, each checked where it
  /// enters naming the key; `check_parameter` refuses a name the material
  /// family does not search, or bounds it does not allow.
  /// std::invalid_argument on bad input; with f.enabled, no target or no
  /// parameter is an error too.
  void read_fit_settings(
      dealii::ParameterHandler &prm, const std::string &where, FitSettings &f,
      const std::function<void(const FitParameter &)> &check_parameter);

  /// A parameter or target name as a fit.csv column ("tensile strength
  /// mean" -> "tensile_strength_mean").
  std::string fit_csv_name(std::string name);
  /// A fit.csv cell as a number; std::invalid_argument naming `where` when
  /// it is not one (whole cell).
  double fit_log_number(const std::string &cell, const std::string &where);
  /// A fit.csv line's cells (a trailing comma: an empty last cell).
  std::vector<std::string> fit_log_cells(const std::string &line);

  /// The header line (with its newline) of fit.csv for the parameters and
  /// targets of `f`: evaluation, stage, each parameter, each target's mean
  /// and sd, objective, all_within_tolerance, seconds, error, note.
  std::string fit_csv_header(const FitSettings &f);

  /// The evaluations of an earlier fit.csv (Fit/resume from; `key` names
  /// it in errors): its header must be fit_csv_header(f), every row whole
  /// (std::invalid_argument naming the key, the file and the line).
  std::vector<FitLogRow> read_fit_log(const std::string &file, const FitSettings &f,
                                      const std::string &key);

  /// The mean and sample standard deviation of each list of per-seed values.
  FitMeasurement summarize_seeds(const std::map<std::string, std::vector<double>> &values,
                                 const std::string                                &error);

  /// Whether a target needs `test` ("ucs", "brazilian", "direct tension",
  /// "triaxial series"): the tests a measurement runs.
  bool fit_needs(const std::vector<std::string> &targets, const std::string &test);

  /// What the search needs of a material family.
  struct FitProblem
  {
    /// The start value of each Fit/parameters entry (same order).
    std::vector<double> initial;
    /// Stiffness parameters: searched first, on the small-strain test.
    std::function<bool(const std::string &name)> is_elastic_parameter;
    /// Measures the material whose Fit/parameters have `values` (same
    /// order) on the `targets`: with `elastic`, only E and nu from a test
    /// stopped at Fit/elastic strain. Failures go into `error`, not throws.
    std::function<FitMeasurement(const std::vector<double>      &values,
                                 const std::vector<std::string> &targets, bool elastic)>
        measure;
  };

  struct FitSearchResult
  {
    std::vector<double> best;        ///< best value of each Fit/parameters entry
    FitMeasurement      measurement; ///< of `best`, on every target
    bool                all_within = false;
  };

  /// The staged search (elastic first when both stiffness parameters and
  /// E/nu targets are given, then the strengths, then every parameter when
  /// the full tests miss a target): writes out/fit.csv (every evaluation),
  /// out/fit.json and out/fit_convergence.svg, with a progress line and ETA
  /// per evaluation on stderr.
  FitSearchResult run_fit_search(const FitSettings &fit, const FitProblem &problem,
                                 const std::string &out);

  /// The evaluations of a fit.csv, read by column names (`evaluation`,
  /// each target's `<name>_mean` and, when present, `<name>_sd`, each
  /// searched parameter, and `error` when present: a row with an error is
  /// left out; '#' lines before the header are notes), as relative errors
  /// against fit.targets. Logs of earlier versions read as well; a missing
  /// column or a cell that is not a number is a std::invalid_argument naming
  /// `what`, the file and the line.
  std::vector<dem::TargetEvaluation> read_fit_evaluations(const std::string &file,
                                                          const FitSettings &fit,
                                                          const std::string &what);

  /// Which targets conflict (dem/specimen/target_front.h): writes
  /// out/fit_front.csv and out/fit_front.json (every pair, every target's
  /// best, the levers), out/fit_front.svg (the pair with the largest
  /// trade-off) and out/fit_levers.csv (what each parameter alone did to
  /// each target); prints each conflicting pair and each target never
  /// reached to `log`.
  dem::TargetFront write_target_front(
      const FitSettings &fit, const std::vector<dem::TargetEvaluation> &evaluations,
      const std::string &out, std::ostream &log);

  /// `demfem calibrate FILE.prm --front FIT.csv` (`where` = FILE.prm): the
  /// targets of FILE.prm's Fit/Targets (at least two) against the
  /// evaluations of an earlier fit's log, into `out` (a run directory of its
  /// own); runs no test. Returns the exit code (0).
  int run_fit_front(const dealii::ParameterHandler &prm, const std::string &where,
                    const FitSettings &fit, const std::string &out,
                    const std::string &fit_csv);

  /// The outcome of a fit whose best material was calibrated successfully:
  /// ok, or targets_not_reached (exit 3) with a message, when a target
  /// stayed outside its tolerance.
  CalibrateOutcome fit_outcome(const FitSearchResult &fit);
} // namespace demfem::apps
