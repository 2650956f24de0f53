#pragma once
// Kirsch's elastic field around an unsupported circular opening of radius a
// (centre at the origin, axis z) in an infinite plane-strain medium under the
// far-field in-plane stress sigma0 (tension positive): the stress an elastic
// rock would carry after the excavation. Demfem study sizes a region with it
// (the zone where sigma1 - sigma3 reaches a fraction of the UCS), and the
// tunnel run says where the elastic rock would reach the material's
// crack-initiation stress (coupling/initiation_zone.h; docs/tunnel.md,
// "Damage measures"). Plain closed forms: no model, no deal.II.
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>

namespace demfem::coupling::kirsch
{
  /// Principal stresses s1 >= s2 of an in-plane stress and the angle phi of
  /// the s1 axis from x.
  struct Principal
  {
    double s1 = 0, s2 = 0, phi = 0;
  };

  inline Principal principal(const Eigen::Matrix2d &s)
  {
    const double c = 0.5 * (s(0, 0) + s(1, 1));
    const double r = std::hypot(0.5 * (s(0, 0) - s(1, 1)), s(0, 1));
    return {c + r, c - r, 0.5 * std::atan2(2 * s(0, 1), s(0, 0) - s(1, 1))};
  }

  /// Polar components {sigma_rr, sigma_tt, sigma_rt} at (r >= a, theta),
  /// theta from the x axis, S1 along phi (Kirsch's solution, written out in
  /// docs/tunnel.md, "Damage measures").
  inline std::array<double, 3> polar_stress(const Eigen::Matrix2d &sigma0, double a,
                                            double r, double theta)
  {
    const Principal p = principal(sigma0);
    const double    m = 0.5 * (p.s1 + p.s2), d = 0.5 * (p.s1 - p.s2);
    const double    p2 = (a / r) * (a / r), p4 = p2 * p2, t = 2 * (theta - p.phi);
    return {{m * (1 - p2) + d * (1 - 4 * p2 + 3 * p4) * std::cos(t),
             m * (1 + p2) - d * (1 + 3 * p4) * std::cos(t),
             -d * (1 + 2 * p2 - 3 * p4) * std::sin(t)}};
  }

  /// Differential stress sigma_max - sigma_min at (r, theta). 2D
  /// (nu_zz < 0): of the in-plane stress. A 3D slab or section (plane
  /// strain, eps_zz = 0 from the unstressed state on, docs/tunnel.md):
  /// sigma_zz = nu_zz (sigma_rr + sigma_tt) is the third principal stress.
  inline double differential_stress(const Eigen::Matrix2d &sigma0, double a, double r,
                                    double theta, double nu_zz = -1)
  {
    const auto   s    = polar_stress(sigma0, a, r, theta);
    const double c    = 0.5 * (s[0] + s[1]);
    const double half = std::hypot(0.5 * (s[0] - s[1]), s[2]);
    if (nu_zz < 0)
      return 2 * half;
    const double zz = nu_zz * (s[0] + s[1]);
    return std::max(c + half, zz) - std::min(c - half, zz);
  }

  /// The far field's differential stress (r -> infinity).
  inline double far_field_differential_stress(const Eigen::Matrix2d &sigma0,
                                              double                 nu_zz = -1)
  {
    const Principal p = principal(sigma0);
    if (nu_zz < 0)
      return p.s1 - p.s2;
    const double zz = nu_zz * (p.s1 + p.s2);
    return std::max(p.s1, zz) - std::min(p.s2, zz);
  }

  /// Largest r >= a at which some theta has differential_stress >= threshold
  /// (a when none; HUGE_VAL when the far field itself reaches it: the zone
  /// is unbounded). Scanned outward on a geometric grid up to 1000 a (the
  /// perturbation decays as (a/r)^2, below 1e-6 of the deviator there),
  /// the last crossing bisected.
  inline double damage_radius(const Eigen::Matrix2d &sigma0, double a, double threshold,
                              double nu_zz = -1)
  {
    if (far_field_differential_stress(sigma0, nu_zz) >= threshold)
      return HUGE_VAL;
    const double phi = principal(sigma0).phi;
    auto         g   = [&](double r) {
      double mx = 0;
      // theta - phi in [0, pi/2]: the field has the period pi and is even
      // in theta - phi (sigma_rr, sigma_tt go with cos, sigma_rt with sin).
      for (int k = 0; k <= 180; ++k)
        mx = std::max(mx,
                                differential_stress(sigma0, a, r, phi + k * M_PI / 360.0, nu_zz));
      return mx - threshold;
    };
    const int n    = 4000;
    double    last = -1;
    for (int i = 0; i <= n; ++i)
      {
        const double r = a * std::pow(1000.0, double(i) / n);
        if (g(r) >= 0)
          last = r;
      }
    if (last < 0)
      return a;
    double lo = last, hi = last * std::pow(1000.0, 1.0 / n);
    for (int it = 0; it < 60; ++it)
      {
        const double mid        = 0.5 * (lo + hi);
        (g(mid) >= 0 ? lo : hi) = mid;
      }
    return 0.5 * (lo + hi);
  }

  /// Area [m^2 per unit length] of {r >= a: differential_stress >=
  /// threshold}, bounded by R = damage_radius(sigma0, a, threshold, nu_zz)
  /// (HUGE_VAL when unbounded): midpoint rule on a polar grid of n_r x
  /// n_theta cells between a and R, whose boundary cells make the error
  /// O((R - a) / n_r) of the zone's width (tests/coupling/
  /// initiation_zone_test.cc bounds it). A caller that has R passes it.
  inline double zone_area_within(const Eigen::Matrix2d &sigma0, double a,
                                 double threshold, double R, double nu_zz = -1,
                                 int n_r = 400, int n_theta = 720)
  {
    if (!(R < HUGE_VAL))
      return HUGE_VAL;
    const double dr = (R - a) / n_r, dt = 2 * M_PI / n_theta;
    double       area = 0;
    for (int i = 0; i < n_r; ++i)
      {
        const double r = a + (i + 0.5) * dr;
        for (int k = 0; k < n_theta; ++k)
          if (differential_stress(sigma0, a, r, (k + 0.5) * dt, nu_zz) >= threshold)
            area += r * dr * dt;
      }
    return area;
  }

  /// The same, R found here.
  inline double zone_area(const Eigen::Matrix2d &sigma0, double a, double threshold,
                          double nu_zz = -1)
  {
    return zone_area_within(sigma0, a, threshold,
                            damage_radius(sigma0, a, threshold, nu_zz), nu_zz);
  }
} // namespace demfem::coupling::kirsch
