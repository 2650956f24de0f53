// Damage measures of the excavation damage zone (coupling/damage_zone.h):
// the zone connected to the wall, percentile depth, sector depths, notch
// orientation and damaged area against hand-computed values of synthetic
// crack sets.
#include <catch2/catch.hpp>

#include "coupling/damage_zone.h"

#include <cmath>

using namespace demfem::coupling;

namespace
{
  std::array<double, 3> polar(double r, double deg, double z = 0)
  {
    return {{r * std::cos(deg * M_PI / 180), r * std::sin(deg * M_PI / 180), z}};
  }
} // namespace

TEST_CASE("damage zone: a symmetric notch pair gives its depth, angle and area",
          "[coupling][damage]")
{
  // Tunnel a = 1 m; ten cracks at 0.1 .. 1.0 m from the wall in the sector
  // centred on 105 deg (90-120) and the same at 285 deg (270-300), plus one
  // stray crack 3 m deep at 15 deg; links 0.15 m long.
  const double                       a = 1.0;
  std::vector<std::array<double, 3>> xy;
  for (int k = 1; k <= 10; ++k)
    {
      xy.push_back(polar(a + 0.1 * k, 105));
      xy.push_back(polar(a + 0.1 * k, 285));
    }
  xy.push_back(polar(a + 3.0, 15));
  const DamageZone z = measure_damage_zone(xy, a, 0.15);
  CHECK(z.cracks == 21);
  // The notches are chains 0.1 m apart from 0.1 m off the wall: connected;
  // the stray crack is not.
  CHECK(z.connected_cracks == 20);
  CHECK(z.link_length == 0.15);
  // Zone: 90th percentile of 20 distances (nearest rank 18): 0.9 m. All
  // cracks: nearest rank 19 of 21: 1.0 m; the stray crack decides only the
  // largest distance.
  CHECK(z.depth == Approx(0.9));
  CHECK(z.depth_all == Approx(1.0));
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
  const DamageZone none = measure_damage_zone({}, 2.0, 0.1);
  CHECK(none.cracks == 0);
  CHECK(none.depth == 0);
  CHECK(none.damaged_area == 0);
  // A uniform ring of 120 cracks 0.5 m deep (ten per sector): every sector
  // 0.5 m, the area the annulus between 2 and 2.5 m.
  std::vector<std::array<double, 3>> ring;
  for (int k = 0; k < 120; ++k)
    ring.push_back(polar(2.5, 3.0 * k + 1.5));
  ring.push_back(polar(1.5, 40)); // inside the opening: distance 0
  // A link of 0 connects every crack (the ring is 0.5 m off the wall).
  const DamageZone z = measure_damage_zone(ring, 2.0, 0.0);
  CHECK(z.connected_cracks == 121);
  for (double d : z.sector_depth)
    CHECK(d == Approx(0.5));
  CHECK(z.damaged_area == Approx(M_PI * (2.5 * 2.5 - 4.0)).epsilon(1e-12));
  CHECK(z.depth == Approx(0.5));
  const auto j = z.to_json();
  CHECK(j.at("sector_depth_m").size() == 12);
  CHECK(j.at("damaged_area_m2").get<double>() == Approx(z.damaged_area));
}

TEST_CASE("damage zone: cracks join the zone through chains no longer than the link",
          "[coupling][damage]")
{
  // Tunnel a = 1 m, link 0.15 m. At 0 deg a chain from 0.1 m off the wall
  // in steps of 0.1 m to 0.5 m, then a gap of 0.2 m, then 0.7 .. 0.9 m; at
  // 180 deg (negative x: cells below zero) a chain 0.1 .. 0.3 m; at 90 deg
  // a cluster 1.0 .. 1.3 m off the wall, never closer than 1.0 m to it.
  const double                       a = 1.0;
  std::vector<std::array<double, 3>> x;
  for (double d : {0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 0.8, 0.9})
    x.push_back(polar(a + d, 0));
  for (double d : {0.1, 0.2, 0.3})
    x.push_back(polar(a + d, 180));
  for (double d : {1.0, 1.1, 1.2, 1.3})
    x.push_back(polar(a + d, 90));
  const std::vector<bool> in       = connected_to_wall(x, a, 0.15);
  const std::vector<bool> expected = {true, true, true, true,  true,  false, false, false,
                                      true, true, true, false, false, false, false};
  CHECK(in == expected);
  const DamageZone z = measure_damage_zone(x, a, 0.15);
  CHECK(z.connected_cracks == 8);
  // Zone distances 0.1 (2x), 0.2 (2x), 0.3 (2x), 0.4, 0.5: nearest rank
  // ceil(7.2) = 8 of 8: 0.5 m. All 15: rank 14: 1.2 m.
  CHECK(z.depth == Approx(0.5));
  CHECK(z.depth_all == Approx(1.2));
  CHECK(z.depth_max == Approx(1.3));
  // A longer link (0.25 m) bridges the 0.2 m gap, not the 0.7 m to the
  // cluster.
  CHECK(measure_damage_zone(x, a, 0.25).connected_cracks == 11);

  // 3D (tunnel along z): a crack above a connected one but 0.3 m along the
  // axis is not linked at 0.15 m, at 0.1 m along the axis it is.
  std::vector<std::array<double, 3>> y = {
      polar(a + 0.1, 45, 0.0), polar(a + 0.2, 45, 0.3), polar(a + 0.2, 45, 0.1)};
  CHECK(connected_to_wall(y, a, 0.15) == std::vector<bool>{true, false, true});
  // Alone, a crack 0.16 m off the wall is beyond a 0.15 m link: no zone.
  CHECK(connected_to_wall({polar(a + 0.16, 45, 1.0)}, a, 0.15) ==
        std::vector<bool>{false});

  // En echelon: link 0.2 m (2 d, d = 0.1 m), cracks 0.1, 0.35 and 0.7 m
  // off the wall, gaps 0.25 and 0.35 m. L = 2 d keeps the first (depth
  // 0.1 m), 3 d (0.3 m) the first two (nearest rank ceil(1.8) = 2: 0.35 m),
  // 4 d (0.4 m) all three (rank 3: 0.7 m); all three in summary.json.
  const DamageZone e = measure_damage_zone(
      {polar(a + 0.1, 30), polar(a + 0.35, 30), polar(a + 0.7, 30)}, a, 0.2);
  CHECK(e.depth == Approx(0.1));
  CHECK(e.depth_longer_links[0] == Approx(0.35));
  CHECK(e.depth_longer_links[1] == Approx(0.7));
  const auto by_link = e.to_json()["depth_by_link"];
  REQUIRE(by_link.size() == 3);
  CHECK(by_link[0]["link_grain_diameters"].get<double>() == 2.0);
  CHECK(by_link[2]["link_grain_diameters"].get<double>() == 4.0);
  CHECK(by_link[2]["depth_m"].get<double>() == Approx(0.7));
  // The same cracks with L = 3 d (0.3 m, Tunnel/damage link length = 3):
  // the first two are the zone (0.35 m), and the sensitivity links are
  // 1.5 L = 4.5 d (0.45 m: all three, 0.7 m) and 2 L = 6 d, reported as such.
  const DamageZone e3 = measure_damage_zone(
      {polar(a + 0.1, 30), polar(a + 0.35, 30), polar(a + 0.7, 30)}, a, 0.3, 3.0);
  CHECK(e3.connected_cracks == 2);
  CHECK(e3.depth == Approx(0.35));
  CHECK(e3.depth_longer_links[0] == Approx(0.7));
  const auto j3 = e3.to_json();
  CHECK(j3["link_grain_diameters"].get<double>() == 3.0);
  CHECK(j3["link_length_m"].get<double>() == Approx(0.3));
  CHECK(j3["depth_by_link"][1]["link_grain_diameters"].get<double>() == 4.5);
  CHECK(j3["depth_by_link"][2]["link_grain_diameters"].get<double>() == 6.0);
  // Every crack connected (link <= 0): the same depth at any link.
  const DamageZone all =
      measure_damage_zone({polar(a + 0.1, 30), polar(a + 0.7, 30)}, a, 0);
  CHECK(all.depth_longer_links[1] == all.depth);
}

TEST_CASE("damage zone: only the zone's cracks near a coupling boundary cut it",
          "[coupling][damage]")
{
  // Tunnel a = 1 m, link 0.15 m, coupling band beyond r0 = 1.45 m. A chain
  // at 0 deg from 0.1 to 0.5 m off the wall reaches the band (r = 1.5 m);
  // an isolated crack at 90 deg, r = 1.8 m, lies in the band too.
  const double                       a = 1.0;
  std::vector<std::array<double, 3>> x;
  for (double d : {0.1, 0.2, 0.3, 0.4, 0.5})
    x.push_back(polar(a + d, 0));
  x.push_back(polar(1.8, 90));
  CHECK(cracks_beyond(x, a, 0.15, 1.45) == std::array<std::size_t, 2>{{2, 1}});
  // Without the chain's last crack only the isolated one is in the band.
  x.erase(x.begin() + 4);
  CHECK(cracks_beyond(x, a, 0.15, 1.45) == std::array<std::size_t, 2>{{1, 0}});
}
