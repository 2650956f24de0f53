// common/statistics.h: the seed statistics of `demfem study`.
#include <catch2/catch.hpp>

#include "common/statistics.h"

using demfem::statistics::mean_interval;

TEST_CASE("statistics: the 95 % confidence interval of a mean uses Student's t",
          "[statistics]")
{
  // 1, 2, 3, 4, 5: mean 3, s = sqrt(2.5); t_{0.975, 4} = 2.776445 (standard
  // tables, e.g. NIST/SEMATECH e-Handbook 1.3.6.7.2), so the half-width is
  // 2.776445 sqrt(2.5) / sqrt(5) = 1.963243.
  const auto i = mean_interval({1, 2, 3, 4, 5});
  CHECK(i.n == 5);
  CHECK(i.mean == Approx(3).epsilon(1e-15));
  CHECK(i.sd == Approx(std::sqrt(2.5)).epsilon(1e-15));
  CHECK(i.half_width == Approx(1.963243).epsilon(1e-6));
  CHECK(i.contains(4.96));
  CHECK_FALSE(i.contains(4.97));
  // Two values: t_{0.975, 1} = 12.7062; 90 %: t_{0.95, 4} = 2.131847.
  CHECK(mean_interval({0, 2}).half_width == Approx(12.7062).epsilon(1e-5)); // s = sqrt(2)
  CHECK(mean_interval({1, 2, 3, 4, 5}, 0.9).half_width ==
        Approx(2.131847 * std::sqrt(2.5) / std::sqrt(5)).epsilon(1e-6));
  // One value: the mean is known, its interval is not and contains nothing.
  const auto one = mean_interval({7});
  CHECK(one.mean == 7);
  CHECK(std::isnan(one.half_width));
  CHECK_FALSE(one.contains(7));
}

TEST_CASE("statistics: two seed means compared by Welch's t test", "[statistics]")
{
  using demfem::statistics::compare_means;
  // Three packings a side with equal scatter s: standard error s sqrt(2/3),
  // Welch-Satterthwaite nu = 4 exactly, t_{0.975, 4} = 2.776445 (tables).
  const double s  = 3;
  const double se = s * std::sqrt(2.0 / 3);
  const auto   c  = compare_means(10 + 2.77 * se, s, 3, 10, s, 3);
  CHECK(c.difference == Approx(2.77 * se).epsilon(1e-14));
  CHECK(c.standard_error == Approx(se).epsilon(1e-15));
  CHECK(c.degrees_of_freedom == Approx(4).epsilon(1e-12));
  CHECK(c.critical == Approx(2.776445).epsilon(1e-6));
  CHECK(c.agree);
  CHECK_FALSE(compare_means(10 + 2.78 * se, s, 3, 10, s, 3).agree);
  // 2.5 standard errors: "different" by the normal two, not at nu = 4.
  CHECK(compare_means(10, s, 3, 10 + 2.5 * se, s, 3).agree); // sign irrelevant
  // Another level: t_{0.90, 4} = 1.533206.
  CHECK(compare_means(10, s, 3, 11, s, 3, 0.8).critical ==
        Approx(1.533206).epsilon(1e-6));
  // A file of one packing whose scatter is the probe's: nu = n - 1 = 2,
  // t_{0.975, 2} = 4.302653, standard error s sqrt(1/3 + 1).
  const auto one = compare_means(12, s, 3, 10, s, 1);
  CHECK(one.degrees_of_freedom == 2);
  CHECK(one.critical == Approx(4.302653).epsilon(1e-6));
  CHECK(one.standard_error == Approx(s * std::sqrt(4.0 / 3)).epsilon(1e-15));
  // Many packings: t tends to the normal 1.96 (nu = 1998: 1.96115).
  CHECK(compare_means(1, 1, 1000, 0, 1, 1000).critical == Approx(1.96115).epsilon(1e-4));
  // Unequal scatters: the probe's UCS of docs/tunnel.md (247 +- 21 MPa,
  // three packings) against its material file's (201 +- 43 MPa, three):
  // standard error 27.6 MPa, nu = 2.90, the difference of 46 MPa is 1.67
  // of them.
  const auto ldb = compare_means(247, 21, 3, 201, 43, 3);
  CHECK(ldb.standard_error ==
        Approx(std::sqrt(21.0 * 21 / 3 + 43.0 * 43 / 3)).epsilon(1e-15));
  const double va = 21.0 * 21 / 3, vb = 43.0 * 43 / 3;
  CHECK(ldb.degrees_of_freedom ==
        Approx((va + vb) * (va + vb) / (va * va / 2 + vb * vb / 2)).epsilon(1e-14));
  CHECK(ldb.degrees_of_freedom == Approx(2.90).epsilon(1e-3));
  CHECK(ldb.agree);
  // Without scatter on either side only equal means agree; no packings or
  // one on each side: unknown.
  CHECK_FALSE(compare_means(1.0001, 0, 3, 1, 0, 3).agree);
  CHECK(compare_means(1, 0, 3, 1, 0, 3).agree);
  CHECK(std::isnan(compare_means(1, 1, 0, 1, 1, 3).standard_error));
  CHECK(std::isnan(compare_means(1, 1, 1, 1, 1, 1).standard_error));
}

TEST_CASE(
    "statistics: a change measured on the same packings, judged against a tolerance",
    "[statistics]")
{
  using demfem::statistics::paired_change;
  // The 2D Lac du Bonnet UCS per packing at 0.25 /s and at 0.125 /s
  // (docs/calibrate_ldb.md): differences -18.7, -29.6, -20.7 MPa, mean
  // -23.0 MPa on a mean of 201.3 MPa: -11.4 %; sd of the differences 5.80
  // MPa, standard error 5.80 / sqrt(3) / 201.3 = 1.66 %. -11.4 % lies more
  // than t_{0.975, 2} = 4.303 of them beyond 2 %: the peak moves.
  const auto slow = paired_change({151.3, 228.4, 224.2}, {132.6, 198.8, 203.5}, 0.02);
  CHECK(slow.n == 3);
  CHECK(slow.change == Approx(-23.0 / 201.3).epsilon(1e-3));
  CHECK(slow.standard_error == Approx(5.8026 / std::sqrt(3.0) / 201.3).epsilon(1e-3));
  CHECK(slow.critical == Approx(4.302653).epsilon(1e-6)); // t table
  CHECK(std::string(slow.verdict) == "moves");
  // -6 % on a mean of 100 with differences -3, -6, -9 (sd 3, standard
  // error 1.73 %): beyond 2 % by 2.3 standard errors, which a normal z = 2
  // called "moves"; with three packings Student's t (4.30) cannot tell.
  const auto few = paired_change({100, 100, 100}, {97, 94, 91}, 0.02);
  CHECK(few.change == Approx(-0.06).epsilon(1e-12));
  CHECK(few.standard_error == Approx(0.03 / std::sqrt(3.0)).epsilon(1e-12));
  CHECK(std::string(few.verdict) == "undecided");
  // The same changes on six packings (t_{0.975, 5} = 2.570582, standard
  // error sqrt(36 / 5) / sqrt(6) = 1.10 %): -6 % +- 2.8 % lies beyond 2 %.
  const auto six =
      paired_change({100, 100, 100, 100, 100, 100}, {97, 94, 91, 97, 94, 91}, 0.02);
  CHECK(six.critical == Approx(2.570582).epsilon(1e-6));
  CHECK(six.standard_error ==
        Approx(std::sqrt(36.0 / 5) / std::sqrt(6.0) / 100).epsilon(1e-12));
  CHECK(std::string(six.verdict) == "moves");
  // 0.125 /s against 0.0625 /s: +22 % and -18 % on two packings, the mean
  // +0.6 %, standard error 13 %: three packings cannot tell 2 % apart.
  const auto chaotic = paired_change({132.6, 198.8, 203.5}, {128.8, 242.9, 166.6}, 0.02);
  CHECK(chaotic.change == Approx((538.3 - 534.9) / 534.9).epsilon(1e-6));
  CHECK(std::string(chaotic.verdict) == "undecided");
  // +0.1 % on every packing: differences 0.1, 0.2, 0.3 (sd 0.1) on a mean
  // of 200, standard error 0.1 / sqrt(3) / 200: within 2 % for sure.
  const auto quiet = paired_change({100, 200, 300}, {100.1, 200.2, 300.3}, 0.02);
  CHECK(quiet.change == Approx(0.001).epsilon(1e-9));
  CHECK(quiet.standard_error == Approx(0.1 / std::sqrt(3.0) / 200).epsilon(1e-9));
  CHECK(std::string(quiet.verdict) == "does not move");
  // One packing: the change, but no standard error and no verdict.
  const auto one = paired_change({100}, {90}, 0.02);
  CHECK(one.change == Approx(-0.1).epsilon(1e-15));
  CHECK(std::isnan(one.standard_error));
  CHECK(std::isnan(one.critical));
  CHECK(std::string(one.verdict) == "undecided");
}
