#pragma once
// Which calibration targets conflict (docs/calibrate.md, "Which targets
// conflict"): from the evaluations of a fit (each a material measured on
// the same packings), for every pair of targets the best each reaches alone,
// the best both reach together, and the pair's Pareto front. A pair
// conflicts when each target is met alone in some evaluation but never both
// in one. The evaluations of a local search are the points it visited, not a
// designed sample: a conflict is what the fit saw, evidence rather than a
// proof that no material meets both.
#include <map>
#include <string>
#include <vector>

namespace demfem::dem
{
  /// A target of the calibration and its tolerance (relative, > 0).
  struct TargetSpec
  {
    std::string name;
    double      tolerance = 0.05;
  };

  /// A searched microparameter and its bounds (hi > lo).
  struct ParameterSpec
  {
    std::string name;
    double      lo = 0, hi = 1;
  };

  /// One evaluation: its number (fit.csv's `evaluation`) and, for each target
  /// it measured, the signed relative error (value - target) / |target| and
  /// the seed standard deviation over |target|; the value of each searched
  /// parameter (in the order of the ParameterSpecs; empty: not known).
  struct TargetEvaluation
  {
    int                           number = 0;
    std::map<std::string, double> relative_error;
    std::map<std::string, double> relative_sd;
    std::vector<double>           parameters;
    /// The fit's stage (fit.csv `stage`): a stage may measure a target by
    /// another test (the elastic stage's E, nu: a small-strain test).
    std::string stage;
  };

  /// The best one target reaches alone, in tolerances: |error| / tolerance.
  struct TargetBest
  {
    std::string name;
    int         evaluations      = 0;     ///< that measured it
    double      normalized_error = 0;     ///< smallest |error| / tolerance (NaN if none)
    int         evaluation       = 0;     ///< where (the first on a tie)
    bool        reached          = false; ///< normalized_error <= 1
  };

  /// Two targets over the evaluations that measured both; errors in
  /// tolerances (n = |relative error| / tolerance).
  struct TargetPairFront
  {
    std::string a, b;
    int         evaluations = 0;
    double      best_a = 0, best_b = 0; ///< smallest n of each alone
    int         evaluation_a = 0, evaluation_b = 0;
    double      best_joint       = 0; ///< smallest max(n_a, n_b): both together
    int         evaluation_joint = 0;
    /// best_joint - max(best_a, best_b) >= 0: how much worse both together
    /// are than the harder of the two alone (0: one evaluation is the best
    /// of both, no trade-off seen).
    double joint_excess = 0;
    /// Each met alone (best_a, best_b <= 1), never together (best_joint > 1).
    bool conflict = false;
    /// The evaluations no other one beats on both n_a and n_b (the pair's
    /// Pareto front), by increasing n_a.
    std::vector<int> front;
  };

  struct TargetFront
  {
    std::vector<TargetBest>      targets; ///< in the order of the specs
    std::vector<TargetPairFront> pairs;   ///< largest joint_excess first
  };

  /// What one parameter alone does to one target, from the pairs of
  /// evaluations of one stage that differ in that parameter only (every
  /// other one bit-identical, as in BOBYQA's first model: the start, then
  /// each parameter alone up and down).
  struct TargetLever
  {
    std::string parameter, target;
    int         pairs = 0; ///< evaluation pairs that differ in this parameter only
    /// Least-squares slope of the target's relative change on the
    /// parameter's change over its range (hi - lo), through the pairs'
    /// differences: the relative change of the target per full range.
    double change_per_range = 0;
    double largest_step     = 0; ///< largest |change| / range of those pairs
    /// Mean seed standard deviation of the target over |target| in those
    /// evaluations (NaN when not logged, 0 with one packing): a change well
    /// below it is not resolved by the packings.
    double seed_sd = 0;
  };

  /// The levers above for every parameter and target with at least one
  /// pair, parameters in their order, targets in theirs. Evaluations whose
  /// `parameters` do not hold one value per spec are left out.
  /// std::invalid_argument for hi <= lo.
  std::vector<TargetLever> one_at_a_time_levers(
      const std::vector<ParameterSpec>    &parameters,
      const std::vector<TargetSpec>       &targets,
      const std::vector<TargetEvaluation> &evaluations);

  /// The analysis above; an evaluation's target without a finite error
  /// (not measured) leaves that evaluation out of the target and its pairs.
  /// std::invalid_argument for a tolerance <= 0 or a repeated target name.
  TargetFront analyse_target_front(const std::vector<TargetSpec>       &targets,
                                   const std::vector<TargetEvaluation> &evaluations);
} // namespace demfem::dem
