// Which calibration targets conflict (dem/specimen/target_front.h): the best
// of each target alone, of each pair together, the pair's Pareto front and
// the conflict flag on a hand-worked set of evaluations. Tolerances and
// errors are dyadic fractions, so every |error| / tolerance is exact in
// binary and the checks are exact equalities.
#include "dem/specimen/target_front.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

using namespace demfem::dem;

TEST_CASE("target pairs: the best alone, together, the front and the conflict",
          "[target_front]")
{
  // Errors in tolerances (A, B, C; - = not measured):
  //   1: 0.5  3    0        A met, B far
  //   2: 4    0.5  0.25     B met, A far
  //   3: 1.5  1.5  -        the closest to both
  //   4: 2    2    0.5      beaten by 3 on A and B
  //   5: -    -    0        C only (ties evaluation 1)
  const std::vector<TargetSpec>       specs = {{"A", 0.125}, {"B", 0.25}, {"C", 0.125}};
  const std::vector<TargetEvaluation> ev    = {
         {1, {{"A", 0.0625}, {"B", 0.75}, {"C", 0.0}}},
         {2, {{"A", -0.5}, {"B", -0.125}, {"C", 0.03125}}},
         {3, {{"A", 0.1875}, {"B", 0.375}}},
         {4, {{"A", 0.25}, {"B", -0.5}, {"C", -0.0625}}},
         {5, {{"A", std::nan("")}, {"C", 0.0}}}};
  const TargetFront f = analyse_target_front(specs, ev);

  REQUIRE(f.targets.size() == 3);
  CHECK(f.targets[0].evaluations == 4); // A: evaluation 5's NaN is "not measured"
  CHECK(f.targets[0].normalized_error == 0.5);
  CHECK(f.targets[0].evaluation == 1);
  CHECK(f.targets[1].normalized_error == 0.5);
  CHECK(f.targets[1].evaluation == 2);
  CHECK(f.targets[2].evaluations == 4);
  CHECK(f.targets[2].normalized_error == 0);
  CHECK(f.targets[2].evaluation == 1); // the first on a tie
  CHECK(f.targets[2].reached);

  REQUIRE(f.pairs.size() == 3);
  // A and B: each met alone (1, 2), together at best 1.5 tolerances (3).
  const TargetPairFront &ab = f.pairs[0]; // the largest trade-off first
  CHECK(ab.a == "A");
  CHECK(ab.b == "B");
  CHECK(ab.evaluations == 4);
  CHECK(ab.best_a == 0.5);
  CHECK(ab.evaluation_a == 1);
  CHECK(ab.best_b == 0.5);
  CHECK(ab.evaluation_b == 2);
  CHECK(ab.best_joint == 1.5);
  CHECK(ab.evaluation_joint == 3);
  CHECK(ab.joint_excess == 1.0);
  CHECK(ab.conflict);
  CHECK(ab.front == std::vector<int>{1, 3, 2}); // by increasing n_A; 4 dominated

  // A and C: evaluation 1 is the best of both: no trade-off.
  const TargetPairFront &ac = f.pairs[1];
  CHECK(ac.a == "A");
  CHECK(ac.b == "C");
  CHECK(ac.evaluations == 3);
  CHECK(ac.best_joint == 0.5);
  CHECK(ac.joint_excess == 0);
  CHECK_FALSE(ac.conflict);
  CHECK(ac.front == std::vector<int>{1});

  // B and C: evaluation 2 meets both; the front still holds 1 (C exact).
  const TargetPairFront &bc = f.pairs[2];
  CHECK(bc.best_joint == 0.5);
  CHECK(bc.evaluation_joint == 2);
  CHECK(bc.joint_excess == 0);
  CHECK_FALSE(bc.conflict);
  CHECK(bc.front == std::vector<int>{2, 1});
}

TEST_CASE("target pairs: a trade-off between targets never met is no conflict; "
          "pairs never measured together come last",
          "[target_front]")
{
  const std::vector<TargetSpec> specs = {{"X", 0.125}, {"Y", 0.125}, {"Z", 0.125}};
  // X and Y: 2 tolerances each alone, 4 together; Z only in evaluation 3.
  const std::vector<TargetEvaluation> ev = {
      {1, {{"X", 0.25}, {"Y", 0.5}}}, {2, {{"X", -0.5}, {"Y", 0.25}}}, {3, {{"Z", 0.0}}}};
  const TargetFront f = analyse_target_front(specs, ev);
  REQUIRE(f.pairs.size() == 3);
  CHECK(f.pairs[0].a == "X");
  CHECK(f.pairs[0].b == "Y");
  CHECK(f.pairs[0].best_joint == 4);
  CHECK(f.pairs[0].joint_excess == 2);
  CHECK_FALSE(f.pairs[0].conflict); // neither is met alone
  CHECK(f.pairs[0].front == std::vector<int>{1, 2});
  CHECK_FALSE(f.targets[0].reached);
  CHECK(f.targets[2].reached);
  for (int k : {1, 2})
    {
      CHECK(f.pairs[k].evaluations == 0);
      CHECK(std::isnan(f.pairs[k].joint_excess));
      CHECK_FALSE(f.pairs[k].conflict);
      CHECK(f.pairs[k].front.empty());
    }
}

TEST_CASE("target pairs: a tolerance <= 0 or a repeated target is refused",
          "[target_front]")
{
  CHECK_THROWS_WITH(analyse_target_front({{"ucs", 0.0}}, {}),
                    Catch::Contains("'ucs'") && Catch::Contains("must be > 0"));
  CHECK_THROWS_WITH(analyse_target_front({{"E", 0.05}, {"E", 0.1}}, {}),
                    Catch::Contains("given twice"));
}

TEST_CASE("levers: what one parameter alone does to a target, from one-at-a-time "
          "pairs",
          "[target_front]")
{
  // p0 in [0, 4], p1 in [0, 2]; BOBYQA's first model around (2, 1): each
  // parameter a quarter of its range up and down. Evaluation 6 moves both
  // (no pair), 7 has no parameters (left out). A responds with slope 1 per
  // range to p0 and, centrally, (0.5 + 0.125) / 0.5 = 1.25 to p1; B is
  // measured in 1 and 2 only. Dyadic numbers: the sums are exact.
  const std::vector<ParameterSpec> params = {{"p0", 0, 4}, {"p1", 0, 2}};
  const std::vector<TargetSpec>    specs  = {{"A", 0.05}, {"B", 0.05}};
  auto ev = [](int n, std::vector<double> p, double a, double b) {
    TargetEvaluation e;
    e.number              = n;
    e.parameters          = p;
    e.relative_error["A"] = a;
    e.relative_sd["A"]    = 0.125;
    if (!std::isnan(b))
      e.relative_error["B"] = b;
    return e;
  };
  const double                        none = std::nan("");
  const std::vector<TargetEvaluation> e    = {ev(1, {2, 1}, 0, 0),
                                              ev(2, {3, 1}, 0.25, 0.5),
                                              ev(3, {1, 1}, -0.25, none),
                                              ev(4, {2, 1.5}, 0.5, none),
                                              ev(5, {2, 0.5}, -0.125, none),
                                              ev(6, {4, 2}, 3, 3),
                                              ev(7, {}, 9, 9)};
  // Evaluation 8 differs from 1 in p0 only but belongs to another stage
  // (another test may measure A there): no pair.
  auto other_stage  = ev(8, {0, 1}, 7, 7);
  other_stage.stage = "elastic";
  auto with_8       = e;
  with_8.push_back(other_stage);
  const auto l = one_at_a_time_levers(params, specs, with_8);
  REQUIRE(l.size() == 3); // p1 has no pair measuring B
  CHECK(l[0].parameter == "p0");
  CHECK(l[0].target == "A");
  CHECK(l[0].pairs == 3);
  CHECK(l[0].change_per_range == 1);
  CHECK(l[0].largest_step == 0.5);
  CHECK(l[0].seed_sd == 0.125);
  CHECK(l[1].target == "B");
  CHECK(l[1].pairs == 1);
  CHECK(l[1].change_per_range == 2);
  CHECK(std::isnan(l[1].seed_sd)); // B's sd not logged
  CHECK(l[2].parameter == "p1");
  CHECK(l[2].pairs == 3);
  CHECK(l[2].change_per_range == 1.25); // the central difference
  CHECK_THROWS_WITH(one_at_a_time_levers({{"c", 2, 2}}, specs, e),
                    Catch::Contains("'c'") && Catch::Contains("must exceed"));
}
