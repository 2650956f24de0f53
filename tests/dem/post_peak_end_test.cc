// The post-peak end of a lab test (dem/specimen/post_peak_end.h): on history
// rows measured in 3D Brazilian tests (docs/calibrate_ldb.md, "The 78 +- 57
// MPa material on packings 10001 and 10002"), loads [N] and cracks so far,
// every 100th row, each fed as one window, with the rule's load fraction 0.7
// and the 3 failure cracks of that disk; and on a synthetic chattering load
// fed step by step, where the window must average the chatter out and the
// end must not depend on the step.
#include "dem/specimen/post_peak_end.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <utility>
#include <vector>

using demfem::dem::PostPeakEnd;

namespace
{
  struct Row
  {
    double      load;
    std::size_t cracks;
  };

  /// Feeds each row as one window (a rule of window 0: every step closes
  /// one) and returns the index of the row that ended the test, or
  /// rows.size().
  std::size_t end_row(PostPeakEnd &rule, const std::vector<Row> &rows)
  {
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rule.add_step(1, rows[i].load) && rule.failed(rows[i].cracks))
        return i;
    return rows.size();
  }

  // Packing 10001: the disk peaked at 690 N (5 % of its strength) with no
  // crack, settled between the platens, and 3 contacts cracked under them
  // while the load rose again to 457 N. The former rule ended the test
  // there and reported a 0.43 MPa "BTS".
  const std::vector<Row> settled = {{0, 0},   {132, 0}, {409, 0}, {668, 0}, {690, 0},
                                    {172, 0}, {169, 0}, {206, 0}, {245, 0}, {161, 0},
                                    {99, 0},  {112, 0}, {333, 2}, {457, 3}};
  // Packing 10000: the split. Cracks grow up to the peak (3626 of them at
  // 13.9 kN) and after it, while the load falls below 0.7 of the peak.
  const std::vector<Row> split = {
      {1571, 0},     {4133, 223},   {7175, 522},   {9989, 988},   {12111, 1328},
      {13074, 2060}, {13650, 3324}, {13912, 3627}, {13234, 4210}, {11841, 4981},
      {9661, 5537},  {8000, 5800},  {7000, 6000}};
} // namespace

TEST_CASE("the post-peak end needs cracking after the peak it falls from", "[labtests]")
{
  SECTION("a disk settling with no crack is not a failure")
  {
    PostPeakEnd rule(0.7, 3, 0);
    CHECK(end_row(rule, settled) == settled.size());
    // The drops from 690 N (to 172), from 245 N (to 161) and from 161 N (to
    // 99) restarted the reference; the load rising again is the reference
    // from there on.
    CHECK(rule.restarts() == 3);
    CHECK(rule.reference_peak() == 457);
    // The same disk loading on to its split ends at the split's drop: the
    // first row below 0.7 x 13 912 N = 9 738 N.
    std::vector<Row> rows = settled;
    for (const Row &r : split)
      rows.push_back({r.load, r.cracks + settled.back().cracks});
    PostPeakEnd       whole(0.7, 3, 0);
    const std::size_t end = end_row(whole, rows);
    REQUIRE(end < rows.size());
    CHECK(rows[end].load == 9661);
    CHECK(whole.reference_peak() == 13912);
  }

  SECTION("a split ends once a window's load falls below the fraction")
  {
    PostPeakEnd       rule(0.7, 3, 0);
    const std::size_t end = end_row(rule, split);
    REQUIRE(end < split.size());
    // 11 841 N > 0.7 x 13 912 = 9 738 N; the next row, 9 661 N, is below.
    CHECK(split[end].load == 9661);
    CHECK(rule.restarts() == 0);
    CHECK(rule.reference_peak() == 13912);
  }

  SECTION("fewer cracks in all than a failure's worth do not end the test")
  {
    // A grain crushed under a platen: two cracks after the peak drop the
    // load, which rises again; a failure needs 3 here.
    const std::vector<Row> crushed = {{0, 0},   {400, 0},  {800, 1}, {1000, 1},
                                      {250, 2}, {250, 2},  {200, 2}, {500, 2},
                                      {900, 2}, {1200, 2}, {1500, 2}};
    PostPeakEnd            rule(0.7, 3, 0);
    CHECK(end_row(rule, crushed) == crushed.size());
    CHECK(rule.restarts() == 0);
    CHECK(rule.reference_peak() == 1500);
  }

  SECTION("a material that never cracks never ends post-peak")
  {
    // Unbonded grains: a friction peak and a drop, no crack at all.
    const std::vector<Row> granular = {{0, 0},   {500, 0}, {900, 0}, {300, 0},
                                       {200, 0}, {150, 0}, {100, 0}};
    PostPeakEnd            rule(0.7, 1, 0);
    CHECK(end_row(rule, granular) == granular.size());
    // 900 -> 300, 300 -> 200 and 150 -> 100 N restart the reference.
    CHECK(rule.restarts() == 3);
  }
}

namespace
{
  /// A load that rises linearly to 1 at t = 1 s and falls linearly to 0 at
  /// t = 2 s, with chatter of amplitude 0.4 and period `period`; the cracks
  /// grow by one per millisecond from the start. Fed step by step with step `dt`;
  /// returns the time at which the rule ends the test (or -1).
  double end_time(PostPeakEnd &rule, double dt, double period)
  {
    const std::size_t n = static_cast<std::size_t>(std::llround(2 / dt));
    for (std::size_t k = 1; k <= n; ++k)
      {
        const double t     = k * dt;
        const double trend = t < 1 ? t : 2 - t;
        const double load  = trend + 0.4 * std::sin(2 * M_PI * t / period);
        if (rule.add_step(dt, load) &&
            rule.failed(static_cast<std::size_t>(std::floor(t / 1e-3))))
          return t;
      }
    return -1;
  }
} // namespace

TEST_CASE("the post-peak window averages chatter out and does not depend on the step",
          "[labtests]")
{
  const double period = 0.01; // the window: one period of the chatter
  // Each window [k W, (k + 1) W] holds one full period, so its mean is the
  // trend's, 2 - (k + 1/2) W after the peak; the largest is 0.995 (the
  // windows either side of t = 1 s), and the first below 0.7 x 0.995 =
  // 0.6965 is k = 130: the test ends when that window closes, at 1.31 s.
  PostPeakEnd  rule(0.7, 3, period);
  const double t = end_time(rule, 1e-4, period);
  CHECK(t == Approx(1.31).margin(1.5e-4)); // one step and round-off
  CHECK(rule.reference_peak() == Approx(0.995).epsilon(1e-3));
  // A step seven times smaller closes the windows within a step of the
  // same times, so the test ends within one (coarse) step of the same time.
  PostPeakEnd  fine(0.7, 3, period);
  const double t_fine = end_time(fine, 1e-4 / 7, period);
  CHECK(std::abs(t_fine - t) <= 1.5e-4);
  // Judged every step, the chatter alone (0.4 deep) drops the load below
  // 0.7 x its last crest within the first period, long before the peak.
  PostPeakEnd  every_step(0.7, 3, 0);
  const double t_step = end_time(every_step, 1e-4, period);
  CHECK(t_step > 0);
  CHECK(t_step < period);
}
