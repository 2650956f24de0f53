// Damage measures of the excavation damage zone (coupling/damage_zone.h):
// percentile depth, sector depths, notch orientation and damaged area
// against hand-computed values of synthetic crack sets.
#include <catch2/catch.hpp>

#include "coupling/damage_zone.h"

#include <cmath>

using namespace demfem::coupling;

namespace
{
  std::array<double, 2> polar(double r, double deg)
  {
    return {{r * std::cos(deg * M_PI / 180), r * std::sin(deg * M_PI / 180)}};
  }
} // namespace

TEST_CASE("damage zone: a symmetric notch pair gives its depth, angle and area",
          "[coupling][damage]")
{
  // Tunnel a = 1 m; ten cracks at 0.1 .. 1.0 m from the wall in the sector
  // centred on 105 deg (90-120) and the same at 285 deg (270-300), plus one
  // stray crack 3 m deep at 15 deg.
  const double                       a = 1.0;
  std::vector<std::array<double, 2>> xy;
  for (int k = 1; k <= 10; ++k)
    {
      xy.push_back(polar(a + 0.1 * k, 105));
      xy.push_back(polar(a + 0.1 * k, 285));
    }
  xy.push_back(polar(a + 3.0, 15));
  const DamageZone z = measure_damage_zone(xy, a);
  CHECK(z.cracks == 21);
  // 90th percentile of 21 distances (nearest rank 19): 1.0 m; the stray
  // crack decides only the largest distance.
  CHECK(z.depth == Approx(1.0));
  CHECK(z.depth_max == Approx(3.0));
  // Sectors of 30 deg: index 3 (90-120) and 9 (270-300) hold ten cracks each,
  // depth the 9th of ten: 0.9 m; the stray crack's sector has one crack (< 3):
  // no damage zone there.
  REQUIRE(z.sector_depth.size() == 12);
  CHECK(z.sector_depth[3] == Approx(0.9));
  CHECK(z.sector_depth[9] == Approx(0.9));
  CHECK(z.sector_depth[0] == 0);
  CHECK(z.notch_depth == Approx(0.9));
  CHECK(z.notch_angle == Approx(105)); // folded into [0, 180)
  // Area: two sectors of pi/6 between r = 1 and 1.9 m.
  const double area = 2 * 0.5 * (M_PI / 6) * (1.9 * 1.9 - 1.0);
  CHECK(z.damaged_area == Approx(area).epsilon(1e-12));
}

TEST_CASE("damage zone: no cracks, and cracks inside the opening count at the wall",
          "[coupling][damage]")
{
  const DamageZone none = measure_damage_zone({}, 2.0);
  CHECK(none.cracks == 0);
  CHECK(none.depth == 0);
  CHECK(none.damaged_area == 0);
  // A uniform ring of 120 cracks 0.5 m deep (ten per sector): every sector
  // 0.5 m, the area the annulus between 2 and 2.5 m.
  std::vector<std::array<double, 2>> ring;
  for (int k = 0; k < 120; ++k)
    ring.push_back(polar(2.5, 3.0 * k + 1.5));
  ring.push_back(polar(1.5, 40)); // inside the opening: distance 0
  const DamageZone z = measure_damage_zone(ring, 2.0);
  for (double d : z.sector_depth)
    CHECK(d == Approx(0.5));
  CHECK(z.damaged_area == Approx(M_PI * (2.5 * 2.5 - 4.0)).epsilon(1e-12));
  CHECK(z.depth == Approx(0.5));
  const auto j = z.to_json();
  CHECK(j.at("sector_depth_m").size() == 12);
  CHECK(j.at("damaged_area_m2").get<double>() == Approx(z.damaged_area));
}
