#pragma once
// Material genesis (fistPkg §4.2): packing (boundary contraction or grain
// scaling, §4.2.1) and finalization (§4.2.2) in a material vessel (§4.1).
#include "dem/engine/model.h"
#include "dem/measure/measurement.h"
#include "dem/specimen/material.h"
#include "dem/specimen/vessel.h"

#include <ostream>
#include <stdexcept>

namespace demfem::dem
{
  template <int dim>
  struct Specimen
  {
    Model<dim>     model;
    Vessel<dim>    vessel;
    MaterialParams material;
    /// Law groups: linear group of the material (packing, non-bonded and new
    /// grain-grain contacts); grain-wall group (frictionless linear);
    /// the bonded-material group (contact bond / parallel bond / flat
    /// joint): one group per law, each contact with its own property block
    /// set by the material's property rules (dem/specimen/property_rules.h).
    int linear_group = -1;
    int wall_group   = -1;
    int bond_group   = -1;

    // Packing record.
    double       packing_pressure = 0; ///< wall-based mean pressure at the end of packing
    double       packing_region_pressure = 0; ///< measurement-region mean pressure
    double       packing_max_force       = 0; ///< max |F| at the end of packing
    double       packing_ratio           = 0; ///< ratio-average at the end of packing
    std::int64_t packing_steps           = 0;
    double       fj_rmul_min             = 0,
           fj_rmul_max = 0; ///< radius multipliers after the validity check

    double porosity() const { return dem::porosity(model, vessel.volume(model.walls)); }
    /// Measurement-based porosity (fistPkg §5.1): the mean over the
    /// vessel's measurement regions (grains counted by centre). Unlike
    /// porosity() it leaves out the loose layer along the walls, which adds
    /// about 0.05 in 3D at 7 grains across (docs/calibrate.md).
    double measurement_porosity() const
    {
      double p = 0;
      for (const auto &r : vessel.regions)
        p += region_porosity(model, r) / vessel.regions.size();
      return p;
    }
    std::size_t n_grains() const { return model.particles.size(); }
  };

  /// Thrown when the packing's forces become non-finite (moduli out of any
  /// physical range): a blow-up, told apart from a packing that is slow.
  struct PackingDiverged : std::runtime_error
  {
    using std::runtime_error::runtime_error;
  };

  /// Builds the specimen: packing then finalization. Progress lines go to
  /// `progress` when given. Throws InputError for bad parameters (nothing
  /// built) and std::runtime_error if packing fails within the step limit.
  template <int dim>
  Specimen<dim> build_specimen(const MaterialParams &p, const VesselParams &v,
                               std::ostream      *progress = nullptr,
                               const std::string &where    = "material");

  /// The two phases of build_specimen, for callers that work between them
  /// (the coupled region carves its disk out of the packing before the
  /// bonds are installed, docs/tunnel.md). `rng` is the genesis stream:
  /// build_specimen seeds it with p.seed and passes it from one phase to the
  /// next, so the phases called in turn give the same specimen.
  /// Packing (§4.2.1) at the material pressure, grains still unbonded.
  template <int dim>
  Specimen<dim> pack_specimen(const MaterialParams &p, const VesselParams &v, Random &rng,
                              std::ostream      *progress = nullptr,
                              const std::string &where    = "material");
  /// Finalization (§4.2.2): the material's contacts, bonds within the
  /// installation gap, flat-jointed microstructure, force-free start.
  /// smooth_vessel = false when the model's walls are not the vessel's (its
  /// walls stay where they are; the caller removes grain-wall overlaps).
  /// `shrunk` (empty, or one value per grain): the radius a grain lost when
  /// the caller shrank it onto its walls after packing; a pair is bonded
  /// within g_i + shrunk_i + shrunk_j, so the packing contacts the shrinking
  /// opened keep their bonds (installed force-free across the opened gap).
  template <int dim>
  void finalize_specimen(Specimen<dim> &s, Random &rng, std::ostream *progress,
                         bool                       smooth_vessel = true,
                         const std::vector<double> &shrunk        = {});

  /// Expected number of grains for p and v (cloud porosity, mean grain volume).
  template <int dim>
  double expected_grain_count(const MaterialParams &p, const VesselParams &v);
  /// Grain radii of the material's size distribution (all pieces, diameter
  /// multiplier applied) whose volumes add up to `solid_volume`, each piece
  /// its volume fraction (fistPkg Table 1), piece after piece.
  template <int dim>
  std::vector<double> draw_radii(const MaterialParams &p, double solid_volume,
                                 Random &rng);
  /// Number-mean grain volume of the material's size distribution.
  template <int dim>
  double mean_grain_volume(const MaterialParams &p);
  /// Sets p.diameter_multiplier so that about n grains fill the vessel.
  template <int dim>
  void set_grain_count(MaterialParams &p, const VesselParams &v, double n);
} // namespace demfem::dem
