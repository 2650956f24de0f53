#pragma once
// The excavation damage zone measured robustly (docs/tunnel.md, "Damage
// measures"), from the in-plane positions of the excavation cracks around a
// tunnel of radius a centred at the origin (along z in 3D). Shared by the
// embedded tunnel and the full-DEM reference so that both are measured the
// same way. Plain geometry: no model, no deal.II.
//
// * the zone: the cracks connected to the wall, a crack being connected when
//   it lies within the link length L of the wall or of a connected crack
//   (L = Tunnel/damage link length mean grain diameters, 2 by default:
//   chains of broken contacts between neighbouring grains). Isolated cracks (an unloading
//   wave's, or a weak bond far out) are counted but not in the zone: they
//   moved the percentile of all cracks by 2x between packings of the same
//   material (docs/study.md, "Damage measured on the zone connected to the
//   wall");
// * depth: the 90th percentile (nearest rank) of the zone's cracks'
//   distances from the wall; the percentile of all cracks (depth_all) and
//   the largest distance of all (depth_max; one stray crack decides it) are
//   their own fields;
// * notch (zone cracks): the wall divided into `sectors` equal angular sectors; a
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
#include <cstdint>
#include <map>
#include <vector>

namespace demfem::coupling
{
  struct DamageZone
  {
    static constexpr double      percentile            = 0.9;
    static constexpr int         sectors               = 12; // 30 degrees
    static constexpr std::size_t min_cracks_per_sector = 3;
    /// Default link length L / mean grain diameter (Tunnel/damage link
    /// length): a broken contact's centroid lies about one diameter from
    /// its neighbours' on the same grain, so two diameters link the cracks
    /// of a chain of grains and not a crack behind an intact grain layer.
    static constexpr double default_link_grain_diameters = 2.0;
    /// The link lengths a caller may choose, in mean grain diameters: below
    /// one diameter neighbouring grains' broken contacts are not linked,
    /// beyond ten the zone is every crack of a typical region.
    static constexpr double min_link_grain_diameters = 1.0;
    static constexpr double max_link_grain_diameters = 10.0;

    std::size_t         cracks               = 0; ///< all cracks measured
    std::size_t         connected_cracks     = 0; ///< in the zone connected to the wall
    double              link_length          = 0; ///< L [m]
    double              link_grain_diameters = default_link_grain_diameters; ///< L / d
    double              depth                = 0; ///< zone: 90th-percentile distance [m]
    double              depth_all            = 0; ///< all cracks: 90th percentile [m]
    double              depth_max            = 0; ///< all cracks: largest distance [m]
    std::vector<double> sector_depth         = std::vector<double>(sectors, 0.0); ///< [m]
    double              notch_depth          = 0; ///< deepest sector [m]
    double              notch_angle          = 0; ///< its centre, in [0, 180) [deg]
    double              damaged_area         = 0; ///< [m^2] per unit length
    /// The zone's depth with longer links, 1.5 L and 2 L (3 and 4 grain
    /// diameters at the default L = 2 d): where the damage is en echelon
    /// (crack chains offset by an intact grain) the depth grows with L, and
    /// these show by how much (the default tunnel example: 0.235, 0.26 and
    /// 0.48 m for L = 2, 3, 4 d).
    static constexpr std::array<double, 2> longer_link_factors = {{1.5, 2.0}};
    std::array<double, 2>                  depth_longer_links{};

    nlohmann::ordered_json to_json() const
    {
      nlohmann::ordered_json j;
      j["cracks"]                    = cracks;
      j["connected_cracks"]          = connected_cracks;
      j["isolated_cracks"]           = cracks - connected_cracks;
      j["link_length_m"]             = link_length;
      j["link_grain_diameters"]      = link_grain_diameters;
      j["depth_percentile"]          = percentile;
      j["depth_m"]                   = depth;
      j["depth_all_m"]               = depth_all;
      j["depth_max_m"]               = depth_max;
      j["sector_width_deg"]          = 360.0 / sectors;
      j["min_cracks_per_sector"]     = min_cracks_per_sector;
      j["sector_depth_m"]            = sector_depth;
      j["notch_depth_m"]             = notch_depth;
      j["notch_angle_deg"]           = notch_angle;
      j["damaged_area_m2"]           = damaged_area;
      nlohmann::ordered_json by_link = nlohmann::ordered_json::array();
      by_link.push_back(
          {{"link_grain_diameters", link_grain_diameters}, {"depth_m", depth}});
      for (std::size_t k = 0; k < longer_link_factors.size(); ++k)
        by_link.push_back(
            {{"link_grain_diameters", longer_link_factors[k] * link_grain_diameters},
             {"depth_m", depth_longer_links[k]}});
      j["depth_by_link"] = by_link;
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

  /// Which cracks (positions x; z = 0 in 2D) are connected to the wall
  /// r = a (in-plane radius; tunnel along z): within `link` of the wall or,
  /// recursively, of a connected crack (3D distance). Breadth-first over
  /// cells of size `link`, O(n log n). link <= 0 connects every crack.
  inline std::vector<bool> connected_to_wall(const std::vector<std::array<double, 3>> &x,
                                             double a, double link)
  {
    std::vector<bool> in(x.size(), !(link > 0));
    if (!(link > 0))
      return in;
    using Cell         = std::array<std::int64_t, 3>;
    const auto cell_of = [&](const std::array<double, 3> &p) {
      return Cell{{static_cast<std::int64_t>(std::floor(p[0] / link)),
                   static_cast<std::int64_t>(std::floor(p[1] / link)),
                   static_cast<std::int64_t>(std::floor(p[2] / link))}};
    };
    std::map<Cell, std::vector<std::size_t>> cells;
    std::vector<std::size_t>                 queue;
    for (std::size_t i = 0; i < x.size(); ++i)
      {
        cells[cell_of(x[i])].push_back(i);
        if (std::hypot(x[i][0], x[i][1]) - a <= link)
          {
            in[i] = true;
            queue.push_back(i);
          }
      }
    while (!queue.empty())
      {
        const std::size_t i = queue.back();
        queue.pop_back();
        const Cell c = cell_of(x[i]);
        for (std::int64_t di = -1; di <= 1; ++di)
          for (std::int64_t dj = -1; dj <= 1; ++dj)
            for (std::int64_t dk = -1; dk <= 1; ++dk)
              {
                const auto it = cells.find(Cell{{c[0] + di, c[1] + dj, c[2] + dk}});
                if (it == cells.end())
                  continue;
                for (const std::size_t j : it->second)
                  if (!in[j] && std::hypot(x[j][0] - x[i][0], x[j][1] - x[i][1],
                                           x[j][2] - x[i][2]) <= link)
                    {
                      in[j] = true;
                      queue.push_back(j);
                    }
              }
      }
    return in;
  }

  /// Cracks at positions x beyond the in-plane radius r0 (a coupling
  /// boundary's band): {all of them, those connected to the wall r = a
  /// through links of `link`}. The zone's make a region too small.
  inline std::array<std::size_t, 2> cracks_beyond(
      const std::vector<std::array<double, 3>> &x, const std::vector<bool> &in, double r0)
  {
    std::array<std::size_t, 2> n{{0, 0}};
    for (std::size_t k = 0; k < x.size(); ++k)
      if (std::hypot(x[k][0], x[k][1]) > r0)
        {
          ++n[0];
          n[1] += in[k];
        }
    return n;
  }

  /// The same, the zone found here (connected_to_wall).
  inline std::array<std::size_t, 2> cracks_beyond(
      const std::vector<std::array<double, 3>> &x, double a, double link, double r0)
  {
    return cracks_beyond(x, connected_to_wall(x, a, link), r0);
  }

  /// The damage zone of cracks at positions x (z = 0 in 2D) around the wall
  /// r = a, its cracks linked within `link` [m] (`link_grain_diameters`
  /// mean grain diameters, which is reported; <= 0: every crack);
  /// `connected` is connected_to_wall(x, a, link), computed once by a
  /// caller that also needs it.
  inline DamageZone measure_damage_zone(
      const std::vector<std::array<double, 3>> &x, double a, double link,
      const std::vector<bool> &connected,
      double link_grain_diameters = DamageZone::default_link_grain_diameters)
  {
    DamageZone                       z;
    std::vector<double>              all, zone;
    std::vector<std::vector<double>> by_sector(DamageZone::sectors);
    const double                     width = 2 * M_PI / DamageZone::sectors;
    for (std::size_t i = 0; i < x.size(); ++i)
      {
        const double d = std::max(0.0, std::hypot(x[i][0], x[i][1]) - a);
        all.push_back(d);
        if (!connected[i])
          continue;
        double t = std::atan2(x[i][1], x[i][0]);
        if (t < 0)
          t += 2 * M_PI;
        const int s = std::min(DamageZone::sectors - 1, static_cast<int>(t / width));
        zone.push_back(d);
        by_sector[s].push_back(d);
      }
    z.cracks               = all.size();
    z.connected_cracks     = zone.size();
    z.link_length          = std::max(0.0, link);
    z.link_grain_diameters = link_grain_diameters;
    z.depth                = nearest_rank_percentile(zone, DamageZone::percentile);
    z.depth_all            = nearest_rank_percentile(all, DamageZone::percentile);
    z.depth_max            = nearest_rank_percentile(all, 1.0);
    z.depth_longer_links.fill(z.depth); // link <= 0: every crack, whatever the link
    for (std::size_t k = 0; k < DamageZone::longer_link_factors.size() && link > 0; ++k)
      {
        const auto longer =
            connected_to_wall(x, a, link * DamageZone::longer_link_factors[k]);
        std::vector<double> d;
        for (std::size_t i = 0; i < x.size(); ++i)
          if (longer[i])
            d.push_back(all[i]);
        z.depth_longer_links[k] = nearest_rank_percentile(d, DamageZone::percentile);
      }
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

  /// The same, the zone found here.
  inline DamageZone measure_damage_zone(
      const std::vector<std::array<double, 3>> &x, double a, double link,
      double link_grain_diameters = DamageZone::default_link_grain_diameters)
  {
    return measure_damage_zone(x, a, link, connected_to_wall(x, a, link),
                               link_grain_diameters);
  }
} // namespace demfem::coupling
