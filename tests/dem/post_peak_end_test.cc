// The post-peak end of a lab test (dem/specimen/post_peak_end.h) on history
// rows measured in 3D Brazilian tests (docs/calibrate_ldb.md, "The 78 +- 57
// MPa material on packings 10001 and 10002"): loads [N] and cracks so far,
// every 100th row, with the rule's load fraction 0.7 and the 3 failure
// cracks of that disk.
#include "dem/specimen/post_peak_end.h"

#include <catch2/catch.hpp>

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

  /// Feeds rows as the lab tests do and returns the index of the row that
  /// ended the test, or rows.size().
  std::size_t end_row(PostPeakEnd &rule, const std::vector<Row> &rows)
  {
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rule.failed(rows[i].load, rows[i].cracks))
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
    PostPeakEnd rule(0.7, 3);
    CHECK(end_row(rule, settled) == settled.size());
    // The drop from 690 N restarted the reference; the load rising again
    // is the reference from there on.
    CHECK(rule.restarts() == 2);
    CHECK(rule.reference_peak() == 457);
    // The same disk loading on to its split ends at the split's drop: the
    // row where the three-row mean first falls below 0.7 x 13 912 N.
    std::vector<Row> rows = settled;
    for (const Row &r : split)
      rows.push_back({r.load, r.cracks + settled.back().cracks});
    PostPeakEnd       whole(0.7, 3);
    const std::size_t end = end_row(whole, rows);
    REQUIRE(end < rows.size());
    CHECK(rows[end].load == 7000);
    CHECK(whole.reference_peak() == 13912);
  }

  SECTION("a split ends once the three-row mean falls below the fraction")
  {
    PostPeakEnd       rule(0.7, 3);
    const std::size_t end = end_row(rule, split);
    REQUIRE(end < split.size());
    // Mean of 11841, 9661 and 8000 N is 9834 N > 0.7 x 13912 = 9738 N; the
    // next row's mean (8220 N) is below it.
    CHECK(split[end].load == 7000);
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
    PostPeakEnd            rule(0.7, 3);
    CHECK(end_row(rule, crushed) == crushed.size());
    CHECK(rule.restarts() == 0);
    CHECK(rule.reference_peak() == 1500);
  }

  SECTION("a material that never cracks never ends post-peak")
  {
    // Unbonded grains: a friction peak and a drop, no crack at all.
    const std::vector<Row> granular = {{0, 0},   {500, 0}, {900, 0}, {300, 0},
                                       {200, 0}, {150, 0}, {100, 0}};
    PostPeakEnd            rule(0.7, 1);
    CHECK(end_row(rule, granular) == granular.size());
    CHECK(rule.restarts() == 2);
  }
}
