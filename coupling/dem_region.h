#pragma once
// The embedded DEM region of the coupled tunnel model (DESIGN §5): a disk of
// bonded grains packed inside a closed ring of wall facets (the continuum's
// interface, boundary id 2) and bonded force-free, as the genesis
// finalization of fistPkg §4.2.2 does for a vessel. 2D only.
//
// Packing (fistPkg §4.2.1, grain scaling): grains are placed at random in the
// disk at a fraction of their size, grown to full size while cycling with
// frictionless linear contacts, and relaxed to equilibrium. Finalization:
// grain-wall overlaps are removed by shrinking the touching grains (the ring
// is the continuum's boundary and cannot move, unlike a vessel wall), and
// every grain pair within the installation gap gets a fully bonded flat
// joint (kn = E*/L, memo Eq. 40), which carries no force when installed.
#include "dem/model.h"

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace demfem::coupling
{
  /// Microparameters of the region's material (a subset of
  /// dem::MaterialParams for a flat-jointed material; SI units).
  struct RegionParams
  {
    double        radius    = 4.0;   ///< outer radius b of the region [m]
    double        d_lo      = 0.16;  ///< smallest grain diameter [m]
    double        d_hi      = 0.24;  ///< largest grain diameter [m]
    double        density   = 2650;  ///< grain density [kg/m^3]
    double        porosity  = 0.16;  ///< target porosity of the packing (2D)
    double        damping   = 0.7;   ///< local damping alpha
    std::uint64_t seed      = 10000; ///< packing seed
    double        lnm_emod  = 4e9;   ///< E* of non-bonded contacts [Pa]
    double        lnm_krat  = 1.5;
    double        lnm_fric  = 0.5;
    double        emod      = 4e9; ///< E* of the flat joints [Pa]
    double        krat      = 1.5;
    double        fric      = 0.6;
    double        igap      = 0; ///< installation gap [m]
    int           fj_Nr     = 2;
    double        fj_ten    = 10e6; ///< tensile strength [Pa]
    double        fj_coh    = 60e6; ///< cohesion [Pa]
    double        fj_fa     = 30;   ///< friction angle [deg]
    bool          breakable = true; ///< false: bonds never break (verification)
    double        wall_fric = 1.0;  ///< grain-ring friction (shear transfer)

    /// Throws dem::InputError naming the key (prefixed by `where`).
    void   validate(const std::string &where) const;
    double mean_diameter() const { return 0.5 * (d_lo + d_hi); }
  };

  /// Law groups of the built region.
  struct RegionGroups
  {
    int              pack = -1, pack_wall = -1; ///< packing (frictionless linear)
    int              linear = -1, wall = -1;    ///< new grain-grain / grain-ring contacts
    std::vector<int> bonds;                     ///< flat-joint groups (binned by L)
    std::size_t      n_bonds    = 0;
    std::size_t      n_rattlers = 0; ///< unbonded grains removed
  };

  /// Fills `model` (which must already hold the closed ring of wall facets
  /// whose vertices lie on the circle of radius p.radius) with the packed and
  /// bonded region. Progress lines go to `progress` when given. Throws
  /// std::runtime_error if packing does not settle.
  RegionGroups build_disk_region(dem::Model<2> &model, const RegionParams &p,
                                 std::ostream *progress = nullptr);

  /// Love-Weber average stress (tension positive) over the grain-grain
  /// contacts whose contact point lies in the disk |x - c| < r, divided by
  /// the disk area (unit thickness).
  Eigen::Matrix2d region_stress(const dem::Model<2> &model, const dem::Vec<2> &c,
                                double r);
} // namespace demfem::coupling
