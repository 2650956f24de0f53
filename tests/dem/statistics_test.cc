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
