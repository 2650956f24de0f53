#pragma once
// Measurement (fistPkg §5.1, Table 8; §3.1): measurement-region stress from
// contact forces and branch vectors, wall-based stress and strain (see
// Vessel), gauge-based strain from sets of grains, porosity, coordination
// and bond counts, and the fabric tensor of contact normals.
// Sign convention: tension positive.
#include "dem/engine/model.h"
#include "dem/specimen/vessel.h"

#include <vector>

namespace demfem::dem
{
  template <int dim>
  using Tensor = Eigen::Matrix<double, dim, dim>;

  /// Average stress in a region, sigma_ij = -(1/V) sum_c F_i l_j (symmetric
  /// part), over the active ball-ball contacts whose contact location lies in
  /// the region (l = x2 - x1, F the force on piece 2) and, when
  /// `include_walls`, ball-wall contacts (l = x_c - x_ball, F on the wall).
  template <int dim>
  Tensor<dim> region_stress(const Model<dim> &m, const Region<dim> &r,
                            bool include_walls = false);

  /// Same over every contact of the model, divided by volume V (e.g. the
  /// vessel volume): the assembly-average (Love-Weber) stress.
  template <int dim>
  Tensor<dim> assembly_stress(const Model<dim> &m, double V, bool include_walls = true);

  /// Mean stress (tension positive): trace / dim.
  template <int dim>
  double mean_stress(const Tensor<dim> &s)
  {
    return s.trace() / dim;
  }

  /// Gauge-based strain (tension positive): symmetric part of the
  /// least-squares displacement gradient of the grains `set` from their
  /// reference positions Particles::x0 to the current positions.
  template <int dim>
  Tensor<dim> gauge_strain(const Model<dim> &m, const std::vector<std::uint32_t> &set);

  /// Grains whose centres lie in the region (for gauge sets).
  template <int dim>
  std::vector<std::uint32_t> grains_in(const Model<dim> &m, const Region<dim> &r);

  /// Porosity 1 - V_grains / V (grain volumes, overlaps not removed, as
  /// fistPkg §4.2.1 n_c); 2D volumes per unit thickness.
  template <int dim>
  double porosity(const Model<dim> &m, double V);
  /// Porosity in a region from the grains whose centres lie in it.
  template <int dim>
  double region_porosity(const Model<dim> &m, const Region<dim> &r);
  /// Porosity in the column of radius `radius` about the z axis: 2D the
  /// disk (region_porosity), 3D the cylinder between z = 0 and `height` (a
  /// slab between its walls), each grain's part inside it exact up to the
  /// quadrature of its slices, overlaps whose contact point lies inside
  /// removed.
  template <int dim>
  double column_porosity(const Model<dim> &m, double radius, double height);

  /// Microstructural counts (fistPkg §3.1).
  struct ContactCounts
  {
    std::size_t grains             = 0; ///< particles
    std::size_t active_grain_grain = 0; ///< active ball-ball contacts
    std::size_t active_grain_wall  = 0;
    double      coordination       = 0; ///< 2 * active ball-ball / grains
    std::size_t bonds = 0; ///< intact cb/pb bonds + flat joints with >= 1 bonded element
    double      bond_coordination = 0; ///< 2 * bonds / grains
    std::size_t fj                = 0; ///< flat-joint contacts
    std::size_t fj_elements = 0, fj_bonded_elements = 0;
    std::size_t fj_bonded = 0; ///< all elements bonded
    std::size_t fj_gapped = 0; ///< no element bonded, g_s > 0
    std::size_t fj_slit   = 0; ///< no element bonded, g_s <= 0
  };
  template <int dim>
  ContactCounts contact_counts(const Model<dim> &m);

  /// Fabric tensor of the active ball-ball contact normals,
  /// Phi = (1/N) sum n (x) n (trace 1); isotropic: eigenvalues all 1/dim.
  /// With a region: only contacts located in it (away from wall effects).
  template <int dim>
  Tensor<dim> fabric_tensor(const Model<dim> &m, const Region<dim> *region = nullptr);

  /// Largest |contact force| over all contacts (for force-free checks).
  template <int dim>
  double max_contact_force(const Model<dim> &m);
} // namespace demfem::dem
