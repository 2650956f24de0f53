#pragma once
// Small fixed-size algebra shared by the DEM engine (Eigen, no deal.II).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>
#include <string>

namespace demfem::dem
{
  /// Position-like vector of the model dimension.
  template <int dim>
  using Vec = Eigen::Matrix<double, dim, 1>;

  /// Number of rotational degrees of freedom: 1 (about z) in 2D, 3 in 3D.
  template <int dim>
  constexpr int rot_dim = (dim == 2 ? 1 : 3);

  /// Rotation-like vector (angular velocity, moment): 2D keeps only the z part.
  template <int dim>
  using RotVec = Eigen::Matrix<double, rot_dim<dim>, 1>;

  /// Error thrown for invalid user input; the message names the parameter,
  /// the offending value and the allowed range.
  struct InputError : std::runtime_error
  {
    using std::runtime_error::runtime_error;
  };

  /// Error thrown when a run becomes unstable (NaN, energy growth, dt above
  /// critical); the message gives the diagnosis.
  struct InstabilityError : std::runtime_error
  {
    using std::runtime_error::runtime_error;
  };

  /// Checks lo <= value (or lo < value when open) and value <= hi (or < hi);
  /// throws InputError naming the parameter, where it came from and the range.
  void check_range(const std::string &where, const std::string &name, double value,
                   double lo, double hi, bool lo_open = false, bool hi_open = false);

  /// Volume of a grain of radius r: a disk of unit thickness (2D) or a ball.
  template <int dim>
  constexpr double ball_volume(double r)
  {
    return dim == 2 ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r;
  }

  /// 2D cross product z-component / scalar-rotation helpers.
  inline double cross2(const Vec<2> &a, const Vec<2> &b)
  {
    return a[0] * b[1] - a[1] * b[0];
  }
} // namespace demfem::dem
