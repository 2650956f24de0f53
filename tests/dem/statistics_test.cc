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

TEST_CASE("statistics: two seed means compared by the standard error of their difference",
          "[statistics]")
{
  using demfem::statistics::compare_means;
  // sd 3 and 4 over 9 and 16 packings: standard error sqrt(9/9 + 16/16) =
  // sqrt(2); a difference of 2.8 lies within 2 of them (2.828), 2.9 not.
  const auto c = compare_means(12.8, 3, 9, 10, 4, 16);
  CHECK(c.difference == Approx(2.8).epsilon(1e-14));
  CHECK(c.standard_error == Approx(std::sqrt(2.0)).epsilon(1e-15));
  CHECK(c.agree);
  CHECK_FALSE(compare_means(12.9, 3, 9, 10, 4, 16).agree);
  CHECK(compare_means(10, 3, 9, 12.9, 4, 16, 2.1).agree); // z given, sign irrelevant
  // Both scatters count: the probe's UCS of docs/tunnel.md (247 +- 21 MPa,
  // three packings) against its material file's (201 +- 43 MPa, three):
  // standard error 27.6 MPa, difference 46 MPa = 1.67 of them.
  const auto ldb = compare_means(247, 21, 3, 201, 43, 3);
  CHECK(ldb.standard_error == Approx(std::sqrt(21.0 * 21 / 3 + 43.0 * 43 / 3)).epsilon(1e-15));
  CHECK(ldb.agree);
  // Without scatter on either side any difference disagrees; no packings: unknown.
  CHECK_FALSE(compare_means(1.0001, 0, 3, 1, 0, 3).agree);
  CHECK(compare_means(1, 0, 3, 1, 0, 3).agree);
  CHECK(std::isnan(compare_means(1, 1, 0, 1, 1, 3).standard_error));
}
