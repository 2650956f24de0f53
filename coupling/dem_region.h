#pragma once
// The embedded DEM region of the coupled tunnel model (docs/architecture.md,
// "Coupling"): grains
// packed inside a closed surface of wall facets (the continuum's interface,
// boundary id 2) and bonded force-free, as the genesis finalization of
// fistPkg §4.2.2 does for a vessel.
//   2D: a disk of disks inside a ring of segments.
//   3D: the slab 0 < z < t of the cylinder r < b, spheres (plane strain
//       through walls): the model holds the lateral ring of
//       triangle facets (add_cylinder_ring, or the continuum's interface
//       vertices); build_region adds the two planar walls z = 0 and z = t,
//       fixed and frictionless, which carry the plane-strain szz.
//
// Genesis (docs/tunnel.md, "The region is the calibrated material"): one
// procedure whether the material comes from a material file or from the
// keys below: the calibration's genesis (dem::pack_specimen, fistPkg
// §4.2.1, and dem::finalize_specimen, §4.2.2) packs the material in a box
// around the region; the region is carved out of it, grains touching the
// ring are shrunk so that no grain-wall contact carries force (the walls are
// the continuum's boundary and cannot move, unlike a vessel wall), and
// grains left without a bond (rattlers) are removed
// (coupling/region_genesis.cc).
#include "dem/engine/model.h"
#include "dem/specimen/material.h"

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace demfem::coupling
{
  /// Microparameters of the region's material (a subset of
  /// dem::MaterialParams for a flat-jointed material; SI units).
  struct RegionParams
  {
    double radius  = 4.0;  ///< outer radius b of the region [m]
    double d_lo    = 0.16; ///< smallest grain diameter [m]
    double d_hi    = 0.24; ///< largest grain diameter [m]
    double density = 2650; ///< grain density [kg/m^3]
    /// Material pressure Pm of the keys' genesis [Pa] (fistPkg §4.2.1: the
    /// packing is scaled until the vessel walls carry Pm); 0: lnm_emod / 800,
    /// a mean grain overlap of about 0.25 % of the radius whatever the
    /// stiffness, and a 2D porosity of about 0.16 (docs/tunnel.md). Unused
    /// with a material file (its Pm_Pa).
    double material_pressure = 0;
    /// 3D: slab thickness t [m] (grains in 0 < z < t).
    double        slab_thickness = 0;
    double        damping        = 0.7;   ///< local damping alpha
    std::uint64_t seed           = 10000; ///< packing seed
    double        lnm_emod       = 4e9;   ///< E* of non-bonded contacts [Pa]
    double        lnm_krat       = 1.5;
    double        lnm_fric       = 0.5;
    double        emod           = 4e9; ///< E* of the flat joints [Pa]
    double        krat           = 1.5;
    double        fric           = 0.6;
    double        igap           = 0; ///< installation gap [m]
    int           fj_Nr          = 2;
    int           fj_Nal         = 4;    ///< 3D: circumferential elements (memo §1.4)
    double        fj_ten         = 10e6; ///< tensile strength [Pa]
    double        fj_coh         = 60e6; ///< cohesion [Pa]
    double        fj_fa          = 30;   ///< friction angle [deg]
    bool          breakable      = true; ///< false: bonds never break (verification)
    double        wall_fric      = 1.0;  ///< grain-ring friction (shear transfer)

    /// Throws dem::InputError naming the key (prefixed by `where`); dim 3
    /// also checks the slab keys.
    void   validate(const std::string &where, int dim = 2) const;
    double mean_diameter() const { return 0.5 * (d_lo + d_hi); }
    /// Scales the grains by k: the size range and, with a material, every
    /// length of its microstructure (size distribution, installation gap,
    /// gapped joints' gaps); stresses and moduli do not change
    /// (docs/tunnel.md, "Grain-size scaling").
    void scale_grains(double k)
    {
      d_lo *= k;
      d_hi *= k;
      if (material)
        {
          material->diameter_multiplier *= k;
          material->igap *= k;
          material->fj_gap.mean *= k;
          material->fj_gap.sd *= k;
        }
    }
    /// Refuse a region whose estimated memory exceeds this [bytes] (<= 0:
    /// half the machine's memory; dem/specimen/memory_budget.h).
    double memory_limit = 0;
    /// The calibrated material (demfem calibrate's material.json, at the
    /// region's grain scale): when set, the region is packed and finalized
    /// by the calibration's genesis (dem::pack_specimen and
    /// dem::finalize_specimen) in a box around the region and carved to it,
    /// with every microstructural property of the material (docs/tunnel.md,
    /// "The region is the calibrated material"); the keys above that the
    /// material also has (sizes, moduli, strengths, density, damping) are
    /// then only what the coupling reads (sizes for the overlap width and
    /// the facet length). Unset: the keys above are the material
    /// (keys_material), packed by the same genesis.
    std::optional<dem::MaterialParams> material;
    /// The flat-jointed material the keys describe (one uniform size piece
    /// d_lo..d_hi, every joint bonded, strengths without spread; unbreakable
    /// bonds carry 1e30 Pa), packed by the same genesis as a material file.
    dem::MaterialParams keys_material() const;
    /// The material the region is packed from: the file's or the keys'.
    dem::MaterialParams genesis_material() const
    {
      return material ? *material : keys_material();
    }
    /// A physical time scale of the region [s]: 2 R / sqrt(E* / rho), the
    /// time a wave at the bonded contacts' bar speed takes to cross it (R
    /// its radius, E* the flat joints' effective modulus, rho the grain
    /// density of genesis_material()). The in-situ ramp lasts Coupling/ramp
    /// crossing times of it (docs/tunnel.md, "In-situ stress installation"),
    /// whatever the time step.
    double crossing_time() const;
  };

  /// Upper bound of Coupling/ramp crossing times: a longer ramp only adds
  /// cost (the slaved layer installs the same state for any length, and a
  /// wall-facet ramp of a few crossing times is already quasi-static).
  constexpr double max_ramp_crossing_times = 1000;

  /// Steps of a load ramp lasting `duration` [s] at the time step dt: the
  /// fewest whose model time reaches the duration, at least one.
  std::int64_t ramp_steps(double duration, double dt);

  /// Law groups of the built region.
  struct RegionGroups
  {
    int         pack = -1, pack_wall = -1; ///< packing (frictionless linear)
    int         linear = -1, wall = -1;    ///< new grain-grain / grain-ring contacts
    int         bond       = -1;           ///< the flat-joint group
    std::size_t n_bonds    = 0;
    std::size_t n_rattlers = 0; ///< unbonded grains removed
    /// 3D: frictionless law of the slab walls and their wall ids (z = 0, t).
    int                slab_wall  = -1;
    std::array<int, 2> slab_walls = {{-1, -1}};
    /// Porosity (grain volume over the volume inside the walls, overlaps
    /// not subtracted) after packing and smoothing, and after the rattlers
    /// were removed.
    double packed_porosity = 0, porosity = 0;
    /// Porosity inside the rim (dem::column_porosity two of the largest
    /// grains inside the ring): the solid fraction that turns the grains'
    /// stress into the continuum's (VTK averaged_stress, the patch tests).
    /// The whole region's porosity counts the carved rim's gaps as well.
    double interior_porosity = 0;
    /// Largest and mean grain-grain overlap over the mean radius at the end
    /// of packing (how tight the packing is).
    double max_overlap_ratio = 0, mean_overlap_ratio = 0;
    /// Steps of the material genesis the region was carved from (its own
    /// model; the region's model starts at step 0).
    std::int64_t genesis_steps = 0;
    /// The genesis packing was an earlier run's in this process, reused
    /// (coupling/genesis_cache.h); its wall time, paid then or now.
    bool   genesis_reused      = false;
    double genesis_wall_time_s = 0;
  };

  /// Fills `model` with the packed and bonded region. 2D: the model must
  /// already hold the closed ring of wall facets whose vertices lie on the
  /// circle of radius p.radius. 3D: the model must hold the closed lateral
  /// surface (triangles) whose vertices lie on the cylinder r = p.radius,
  /// 0 <= z <= p.slab_thickness; the slab walls are added here. Progress
  /// lines go to `progress` when given. Throws std::runtime_error if packing
  /// does not settle, dem::InputError for bad parameters or walls.
  template <int dim>
  RegionGroups build_region(dem::Model<dim> &model, const RegionParams &p,
                            std::ostream *progress = nullptr);

  /// The region carved out of the calibration genesis of
  /// p.genesis_material(); called by build_region with the groups of the
  /// slab walls (3D) already set and `inner` the radius of the largest
  /// circle inside the ring (coupling/region_genesis.cc).
  template <int dim>
  RegionGroups carve_region(dem::Model<dim> &model, const RegionParams &p, double inner,
                            RegionGroups G, std::ostream *progress);

  /// The 2D region (the API the 2D models use).
  inline RegionGroups build_disk_region(dem::Model<2> &model, const RegionParams &p,
                                        std::ostream *progress = nullptr)
  {
    return build_region<2>(model, p, progress);
  }

  /// Adds a wall of triangle facets on the lateral surface of the cylinder
  /// r = radius, 0 <= z <= thickness: n_around x n_layers straight-chord
  /// quads (vertices on the circle), each split into two triangles; returns
  /// the wall id.
  int add_cylinder_ring(dem::Walls<3> &walls, double radius, double thickness,
                        unsigned int n_around, unsigned int n_layers,
                        const std::string &name);

  /// Love-Weber average stress (tension positive) over the grain-grain
  /// contacts whose contact point lies in the disk |x - c| < r, divided by
  /// the disk area (unit thickness).
  Eigen::Matrix2d region_stress(const dem::Model<2> &model, const dem::Vec<2> &c,
                                double r);
  /// 3D slab: Love-Weber average stress (tension positive) over the contacts
  /// whose contact point lies in the cylinder |(x - c)_xy| < r (any z),
  /// divided by pi r^2 thickness. Ball-wall contacts (the slab walls) count
  /// with the branch from the grain centre to the contact point, so szz is
  /// the wall force per area.
  Eigen::Matrix3d region_stress(const dem::Model<3> &model, const dem::Vec<3> &c,
                                double r, double thickness);
  /// 3D: the same over the contacts whose contact point lies in the
  /// cylinder |(x - c)_xy| < r, z0 <= z <= z1, divided by pi r^2 (z1 - z0)
  /// (a tunnel section's free core between its end layers).
  Eigen::Matrix3d region_stress(const dem::Model<3> &model, const dem::Vec<3> &c,
                                double r, double z0, double z1);
} // namespace demfem::coupling
