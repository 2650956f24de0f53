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

  /// One evaluation: its number (fit.csv's `evaluation`) and, for each target
  /// it measured, the signed relative error (value - target) / |target|.
  struct TargetEvaluation
  {
    int                           number = 0;
    std::map<std::string, double> relative_error;
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

  /// The analysis above; an evaluation's target without a finite error
  /// (not measured) leaves that evaluation out of the target and its pairs.
  /// std::invalid_argument for a tolerance <= 0 or a repeated target name.
  TargetFront analyse_target_front(const std::vector<TargetSpec>       &targets,
                                   const std::vector<TargetEvaluation> &evaluations);
} // namespace demfem::dem
