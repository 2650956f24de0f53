// The one instability monitor (common/growth_monitor.h) against sequences
// whose answer is known: a constant ratio per step (an unstable explicit
// integration), a power of time from rest (a ramped load, stable), values
// below the round-off floor, growth from zero, non-finite values.
#include "common/growth_monitor.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace demfem::instability;

namespace
{
  /// Steps until the monitor reports, feeding value(n) for n = 1, 2, ...;
  /// 0 if it never does within `limit` steps.
  template <class F>
  int steps_to_report(const GrowthRule &rule, F value, int limit = 200, double floor = 0)
  {
    GrowthMonitor m(rule);
    for (int n = 1; n <= limit; ++n)
      if (m.update(value(n), floor))
        return n;
    return 0;
  }
} // namespace

TEST_CASE("growth monitor: a constant ratio per step is an instability", "[instability]")
{
  // Ratio 2 from 1e-20: growth from the first step (previous value 0 counts
  // with from_zero), so the 15th value completes the streak. The DEM rule
  // compares the first five log-ratios of the streak with the last five:
  // the first, from zero, is infinite, so it reports one step later, when
  // that ratio has left the window.
  const auto geometric = [](int n) { return 1e-20 * std::pow(2.0, n); };
  CHECK(steps_to_report(dem_kinetic_energy, geometric) == 16);
  CHECK(steps_to_report(continuum_kinetic_energy, geometric) == 15);
  // The residual rule does not count growth from zero: one step later.
  CHECK(steps_to_report(interface_residual, geometric) == 16);
  // A ratio just below the factor is never growth.
  CHECK(steps_to_report(dem_kinetic_energy, [](int n) { return std::pow(1.49, n); }) ==
        0);
}

TEST_CASE("growth monitor: a power of time from rest is not an instability for the DEM",
          "[instability]")
{
  // Kinetic energy ~ t^8 (a ramped load a few elements away): ratios
  // (1 + 1/n)^8 = 256, 25.6, 9.99, ... stay above 1.5 for n < 19, so 15
  // consecutive growth steps happen, but the ratios fall: the DEM rule
  // (constant_ratio_only) does not report it; the continuum rule, without
  // that test, does.
  const auto power = [](int n) { return std::pow(double(n), 8); };
  CHECK(steps_to_report(dem_kinetic_energy, power) == 0);
  CHECK(steps_to_report(continuum_kinetic_energy, power) == 15);
}

TEST_CASE("growth monitor: round-off floor, interruption, non-finite", "[instability]")
{
  // Below the floor nothing counts, however fast it grows (the 1e-51 J
  // numerical wave tail of a slaved layer).
  CHECK(steps_to_report(
            dem_kinetic_energy, [](int n) { return 1e-60 * std::pow(2.0, n); }, 100,
            1e-20) == 0);
  // One step without growth restarts the streak (n = 10); the streak's first
  // ratio, 2^11 / 1, is large, so the DEM rule waits until it leaves the
  // window of the first five: 15 growth steps from n = 11 end at 25, one
  // more at 26. Without the constant-ratio test, 25.
  const auto interrupted = [](int n) { return n == 10 ? 1.0 : std::pow(2.0, n); };
  CHECK(steps_to_report(dem_kinetic_energy, interrupted) == 26);
  CHECK(steps_to_report(continuum_kinetic_energy, interrupted) == 25);
  // A non-finite value is reported at once.
  GrowthMonitor m(interface_residual);
  CHECK_FALSE(m.update(0.5));
  CHECK(m.update(std::numeric_limits<double>::quiet_NaN()));
  CHECK(m.update(HUGE_VAL));
  CHECK_THROWS_AS(GrowthMonitor(GrowthRule{1.5, 30, true, true}), std::invalid_argument);
}
