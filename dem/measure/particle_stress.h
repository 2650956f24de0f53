#pragma once
// Per-grain averaged stress, the "averaged_stress" array of the particles'
// VTK output (.vtp; docs/architecture.md, "VTK files").
//
// The Love-Weber average stress of a grain p with volume V_p (2D: unit
// thickness) from the forces F_c its contacts exert on it at the contact
// points x_c (fistPkg §5.1, measurement-based stress, applied to one grain):
//   sigma_p = (phi / V_p) sym( sum_c (x_c - x_p) (x) F_c ),
// tension positive. With phi = 1 it is the stress inside the grain; with phi the
// solid fraction (1 - porosity) of the assembly it is the grain's share of the
// continuum-equivalent stress, so that the volume average over the grains of a
// region equals the region's measurement-based average stress
//   sigma = (1/V) sum_p sum_c (x_c - x_p) (x) F_c,   V = sum_p V_p / phi.
// Moments of the contacts only enter the antisymmetric part and are dropped.
#include "dem/engine/model.h"

#include <Eigen/Dense>

#include <vector>

namespace demfem::dem
{
  template <int dim>
  using StressTensor = Eigen::Matrix<double, dim, dim>;

  /// One tensor per particle (model order). Throws InputError if
  /// solid_fraction is not in (0, 1].
  template <int dim>
  std::vector<StressTensor<dim>> grain_stresses(const Model<dim> &model,
                                                double            solid_fraction = 1.0);
} // namespace demfem::dem
