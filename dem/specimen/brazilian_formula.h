#pragma once
// The Brazilian strength formula (fistPkg Eq. 24) and its flattened-disk
// factor; free of Eigen so that the fem/ check of the factor
// (tests/fem/test_brazilian_flat.cc) includes it.
#include <cmath>

namespace demfem::dem
{
  /// Largest Brazilian flat angle 2 alpha [deg] accepted: up to 20 deg the
  /// arc-load factor below holds for flats under rigid platens to +0.5 /
  /// -2.5 % (the fem/ check, tests/fem/test_brazilian_flat.cc); at 30 deg
  /// a rigid punch's centre stress falls 5 % below it.
  inline constexpr double max_brazilian_flat_angle = 20;

  /// Centre-stress factor of a disk loaded over two opposite arcs of
  /// 2 alpha [rad] each (Hondros' arc-load solution at the centre):
  /// sigma_t = k F / (pi R t) with k = sin(2 alpha) / alpha - 1, which tends
  /// to 1 (Eq. 24) as alpha -> 0 (0.960 at 2 alpha = 20 deg). A flattened
  /// disk's flats of 2 alpha carry the same centre stress to within the
  /// fem/ check of tests/fem/test_brazilian_flat.cc (docs/calibrate.md,
  /// "The flattened Brazilian disk").
  inline double brazilian_arc_factor(double alpha)
  {
    return alpha > 1e-6 ? std::sin(2 * alpha) / alpha - 1 : 1 - 4 * alpha * alpha / 3;
  }

  /// Brazilian tensile strength, fistPkg Eq. 24: sigma_t = F_max / (pi R t)
  /// (2D: t = 1); a flattened disk with flats of 2 alpha = flat_angle [deg]
  /// scales it by brazilian_arc_factor(alpha).
  inline double brazilian_strength(double F_max, double R, double t,
                                   double flat_angle_deg = 0)
  {
    return brazilian_arc_factor(0.5 * flat_angle_deg * M_PI / 180) * F_max /
           (M_PI * R * t);
  }

} // namespace demfem::dem
