#pragma once
// Reuse of the region's genesis packing within one process (docs/study.md,
// "Packing reuse"). A sweep runs the same region (material, grain size,
// region radius, slab thickness, seed) under many scheme settings; the
// genesis packing is deterministic, so it is packed once and every later
// run carves its region out of the same grains. What carve_region reads
// from the packed box is kept, with the genesis random stream after the
// packing (the finalization draws from it next), so a reused packing gives
// the region bit for bit.
#include "dem/specimen/genesis.h"

#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace demfem::coupling
{
  /// What carve_region needs of a packed genesis box.
  template <int dim>
  struct PackedBox
  {
    std::vector<dem::Vec<dim>> x;                      ///< grain centres (vessel frame)
    std::vector<double>        radius, mass;           ///< per grain
    double                     max_overlap_ratio  = 0; ///< largest overlap / mean radius
    double                     mean_overlap_ratio = 0; ///< mean overlap / mean radius
    double                     porosity           = 0; ///< of the packed box
    std::int64_t               steps              = 0; ///< genesis steps
    double                     wall_time_s        = 0; ///< wall time the packing took
    dem::Random                rng{0};                 ///< genesis stream after packing
  };

  /// The packed box of material `mat` in vessel `v`: packed by
  /// dem::pack_specimen on the first call, returned from memory on later
  /// calls with the same packing inputs (`reused` says which). Only the
  /// inputs that the packing reads form the key (sizes, density, damping,
  /// seed, the packing's linear contacts, the packing keys and the vessel);
  /// the bonds and strengths are the finalization's and may differ between
  /// the runs sharing a box. The last `capacity` boxes are kept (8).
  template <int dim>
  std::shared_ptr<const PackedBox<dim>> packed_box(const dem::MaterialParams &mat,
                                                   const dem::VesselParams   &v,
                                                   std::ostream              *progress,
                                                   const std::string         &where,
                                                   bool                      &reused);

  /// Forgets every kept box (tests; a process that needs the memory back).
  void clear_packed_boxes();
} // namespace demfem::coupling
