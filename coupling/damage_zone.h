#pragma once
// The excavation damage zone measured robustly (docs/tunnel.md, "Damage
// measures"), from the in-plane positions of the excavation cracks around a
// tunnel of radius a centred at the origin (along z in 3D). Shared by the
// embedded tunnel and the full-DEM reference so that both are measured the
// same way. Plain geometry: no model, no deal.II.
//
// * depth: the 90th percentile (nearest rank) of the cracks' distances
//   from the wall; the largest distance is its own field (one stray crack
//   decides it);
// * notch: the wall divided into `sectors` equal angular sectors; a
//   sector's depth is the 90th percentile of the distances of its cracks
//   when it holds at least `min_cracks_per_sector` of them, else 0 (a lone
//   crack is not a damage zone); the notch is the deepest sector, its angle
//   the sector's centre folded into [0, 180) degrees (a tunnel under a
//   uniform far field breaks out in opposite pairs);
// * damaged area: the area between the wall and the sector depths,
//   sum over sectors of (dtheta / 2) ((a + d_s)^2 - a^2) [m^2; per unit
//   length of tunnel].
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace demfem::coupling
{
  struct DamageZone
  {
    static constexpr double      percentile            = 0.9;
    static constexpr int         sectors               = 12; // 30 degrees
    static constexpr std::size_t min_cracks_per_sector = 3;

    std::size_t         cracks       = 0;
    double              depth        = 0; ///< 90th-percentile distance [m]
    double              depth_max    = 0; ///< largest distance [m]
    std::vector<double> sector_depth = std::vector<double>(sectors, 0.0); ///< [m]
    double              notch_depth  = 0; ///< deepest sector [m]
    double              notch_angle  = 0; ///< its centre, in [0, 180) [deg]
    double              damaged_area = 0; ///< [m^2] per unit length

    nlohmann::ordered_json to_json() const
    {
      nlohmann::ordered_json j;
      j["cracks"]                = cracks;
      j["depth_percentile"]      = percentile;
      j["depth_m"]               = depth;
      j["depth_max_m"]           = depth_max;
      j["sector_width_deg"]      = 360.0 / sectors;
      j["min_cracks_per_sector"] = min_cracks_per_sector;
      j["sector_depth_m"]        = sector_depth;
      j["notch_depth_m"]         = notch_depth;
      j["notch_angle_deg"]       = notch_angle;
      j["damaged_area_m2"]       = damaged_area;
      return j;
    }
  };

  /// Nearest-rank percentile q (0 < q <= 1) of d: the smallest value with at
  /// least q of the values at or below it; 0 for no value.
  inline double nearest_rank_percentile(std::vector<double> d, double q)
  {
    if (d.empty())
      return 0;
    const auto rank = static_cast<std::size_t>(std::ceil(q * d.size()));
    const auto k    = std::min(d.size() - 1, rank > 0 ? rank - 1 : 0);
    std::nth_element(d.begin(), d.begin() + k, d.end());
    return d[k];
  }

  /// The damage zone of cracks at in-plane positions (x, y) around the wall
  /// r = a.
  inline DamageZone measure_damage_zone(const std::vector<std::array<double, 2>> &xy,
                                        double                                    a)
  {
    DamageZone                       z;
    std::vector<double>              all;
    std::vector<std::vector<double>> by_sector(DamageZone::sectors);
    const double                     width = 2 * M_PI / DamageZone::sectors;
    for (const auto &p : xy)
      {
        const double d = std::max(0.0, std::hypot(p[0], p[1]) - a);
        double       t = std::atan2(p[1], p[0]);
        if (t < 0)
          t += 2 * M_PI;
        const int s = std::min(DamageZone::sectors - 1, static_cast<int>(t / width));
        all.push_back(d);
        by_sector[s].push_back(d);
      }
    z.cracks    = all.size();
    z.depth     = nearest_rank_percentile(all, DamageZone::percentile);
    z.depth_max = nearest_rank_percentile(all, 1.0);
    for (int s = 0; s < DamageZone::sectors; ++s)
      {
        const double d =
            by_sector[s].size() >= DamageZone::min_cracks_per_sector
                ? nearest_rank_percentile(by_sector[s], DamageZone::percentile)
                : 0.0;
        z.sector_depth[s] = d;
        z.damaged_area += 0.5 * width * ((a + d) * (a + d) - a * a);
        if (d > z.notch_depth)
          {
            z.notch_depth = d;
            z.notch_angle = std::fmod((s + 0.5) * 360.0 / DamageZone::sectors, 180.0);
          }
      }
    return z;
  }
} // namespace demfem::coupling
