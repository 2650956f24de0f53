#pragma once
// Where the excavation cracks lie against the elastic prediction
// (docs/tunnel.md, "Damage measures"): the zone around the opening where
// Kirsch's elastic stress after the excavation reaches a crack-initiation
// stress of the material, sigma1 - sigma3 >= sigma_ci (the
// differential-stress damage-initiation criterion of brittle rock, whose
// threshold is the unconfined crack-initiation stress: the lab's volumetric
// one, or the first cracks by crack count). A rock that cracks as its lab
// specimens did cracks inside it; cracks outside it come from something the
// elastic field does not have (the grains' own stress scatter, a weak-bond
// tail, the excavation's dynamics). Plain geometry on the cracks' in-plane
// positions: no model, no deal.II.
#include "coupling/kirsch.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace demfem::coupling
{
  struct InitiationZone
  {
    std::string name;          ///< which crack-initiation stress (a material.json key)
    double      threshold = 0; ///< sigma_ci [Pa]
    /// The in-situ differential stress already reaches sigma_ci: the whole
    /// rock mass is in its cracking range (the zone is unbounded).
    bool        far_field_exceeds = false;
    double      depth             = 0; ///< largest distance of the zone from the wall [m]
    double      area              = 0; ///< [m^2 per unit length of tunnel]
    std::size_t cracks = 0, cracks_inside = 0;           ///< excavation cracks
    std::size_t zone_cracks = 0, zone_cracks_inside = 0; ///< those connected to the wall
    /// A crack is a broken contact between grains, its position the
    /// contact's, while the stress that broke it is the grains': the zone is
    /// resolved to about a grain. Cracks within `near` (one mean grain
    /// diameter) of the zone are counted too.
    double      near        = 0;
    std::size_t cracks_near = 0, zone_cracks_near = 0;

    nlohmann::ordered_json to_json() const
    {
      nlohmann::ordered_json j;
      j["crack_initiation_key"] = name;
      j["crack_initiation_Pa"]  = threshold;
      j["far_field_exceeds"]    = far_field_exceeds;
      j["depth_m"] =
          far_field_exceeds ? nlohmann::ordered_json() : nlohmann::ordered_json(depth);
      j["area_m2"] =
          far_field_exceeds ? nlohmann::ordered_json() : nlohmann::ordered_json(area);
      // The zone's depth in mean grain diameters: below about 3 the measured
      // damage depth counts grain layers (docs/tunnel.md, "Damage measures").
      j["depth_grain_diameters"]        = far_field_exceeds || !(near > 0)
                                              ? nlohmann::ordered_json()
                                              : nlohmann::ordered_json(depth / near);
      j["cracks"]                       = cracks;
      j["cracks_inside"]                = cracks_inside;
      j["cracks_outside"]               = cracks - cracks_inside;
      j["connected_cracks"]             = zone_cracks;
      j["connected_cracks_inside"]      = zone_cracks_inside;
      j["connected_cracks_outside"]     = zone_cracks - zone_cracks_inside;
      j["near_m"]                       = near;
      j["cracks_within_near"]           = cracks_near;
      j["connected_cracks_within_near"] = zone_cracks_near;
      return j;
    }
  };

  /// summary.json's "elastic_initiation_zones": one object per zone.
  inline nlohmann::ordered_json to_json(const std::vector<InitiationZone> &zones)
  {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (const auto &z : zones)
      a.push_back(z.to_json());
    return a;
  }

  /// The elastic zone of `threshold` (named `name`) around the opening r = a
  /// under the in-plane in-situ stress sigma0, and how many of the cracks at
  /// positions x (z ignored; `connected` marks the damage zone's,
  /// coupling/damage_zone.h) lie in it. nu_zz < 0: 2D (in-plane
  /// differential stress); else a 3D slab or section in plane strain,
  /// sigma_zz = nu_zz (sigma_rr + sigma_tt) (coupling/kirsch.h). A crack
  /// inside the opening (a grain that moved in) is judged at the wall. A
  /// crack is within `near` of the zone when the zone holds its position
  /// or one of 32 points on the circles of radius near/2 and near around it
  /// (16 directions each: the zone's boundary curves on the scale of the
  /// opening, much larger than near).
  inline InitiationZone measure_initiation_zone(
      const std::vector<std::array<double, 3>> &x, const std::vector<bool> &connected,
      const Eigen::Matrix2d &sigma0, double a, const std::string &name, double threshold,
      double near, double nu_zz = -1)
  {
    InitiationZone z;
    z.name             = name;
    z.threshold        = threshold;
    z.near             = near;
    const auto in_zone = [&](double px, double py) {
      const double r = std::max(a, std::hypot(px, py));
      return kirsch::differential_stress(sigma0, a, r, std::atan2(py, px), nu_zz) >=
             threshold;
    };
    const double R      = kirsch::damage_radius(sigma0, a, threshold, nu_zz);
    z.far_field_exceeds = !(R < HUGE_VAL);
    if (!z.far_field_exceeds)
      {
        z.depth = R - a;
        z.area  = kirsch::zone_area_within(sigma0, a, threshold, R, nu_zz);
      }
    z.cracks = x.size();
    for (std::size_t i = 0; i < x.size(); ++i)
      {
        const bool inside = in_zone(x[i][0], x[i][1]);
        bool       close  = inside;
        for (int k = 0; k < 32 && !close; ++k)
          {
            const double rho = (k < 16 ? 0.5 : 1.0) * near, t = (k % 16) * M_PI / 8;
            close = in_zone(x[i][0] + rho * std::cos(t), x[i][1] + rho * std::sin(t));
          }
        z.cracks_inside += inside;
        z.cracks_near += close;
        if (connected[i])
          {
            ++z.zone_cracks;
            z.zone_cracks_inside += inside;
            z.zone_cracks_near += close;
          }
      }
    return z;
  }
} // namespace demfem::coupling
