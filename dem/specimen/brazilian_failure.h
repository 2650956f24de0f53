#pragma once
// Failure mode of a Brazilian (diametral compression) test from its cracks
// (docs/calibrate.md, "Failure mode of the Brazilian test"). A valid test
// splits along the loaded diameter (ISRM 1978 suggested method): the
// elastic disk is in uniform tension 2F/(pi D t) across the middle of that
// diameter and the fracture starts at the centre, so the BTS of Eq. 24
// (fistPkg §5.6) is a tensile strength only then. A disk crushed under the
// platens, or damaged all over, carries a higher load that is no tensile
// strength (measured: a 1000-grain disk rose to 40.7 MPa with 371 cracks
// where two other packings of the same material split at 6-9 MPa).
#include "dem/engine/types.h"

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace demfem::dem
{
  /// The split zone: the central strip of width D/3 about the loaded
  /// diameter (|x - x_c| < R/3, x the lateral axis 0) without the D/6 next
  /// to each platen (|y - y_c| < 2R/3, y the loading axis dim - 1; 3D: the
  /// cylinder's axis, y, is not constrained). The platen ends are left out
  /// because cracks there are the contacts crushing, not the split.
  /// Reference fractions of the cracks in it: a straight diametral split
  /// cracked uniformly from platen to platen 2/3; cracks spread uniformly
  /// over the disk 8/(9 pi) = 0.283 (the zone's share of the disk area: the
  /// zone is a 2R/3 x 4R/3 rectangle, inside the disk); cracks confined to
  /// the platen ends 0.
  constexpr double split_zone_half_width  = 1.0 / 3; ///< of R
  constexpr double split_zone_half_length = 2.0 / 3; ///< of R

  struct BrazilianFailure
  {
    /// "split": at least `threshold` of the cracks lie in the split zone;
    /// "not_split": cracks, but fewer there (crushed at the platens, or
    /// spread); "no_failure": no crack, nothing failed.
    std::string mode;
    std::size_t cracks = 0, in_zone = 0;
    /// in_zone / cracks; NaN without cracks.
    double fraction = std::numeric_limits<double>::quiet_NaN();
  };

  /// Classifies crack `positions` (at breakage) of a disk (2D) or a cylinder
  /// with its axis along y (3D) of radius R centred on `centre`, loaded
  /// along axis dim - 1. threshold in (0, 1].
  template <int dim>
  BrazilianFailure classify_brazilian_failure(const std::vector<Vec<dim>> &positions,
                                              const Vec<dim> &centre, double R,
                                              double threshold);

  /// How many of a test's last cracks (in order of breakage) are its
  /// failure, the cracks the mode is decided on: those formed after the
  /// peak (they dropped the load and ended the test; measured, the crushed
  /// disk's were at a platen, the splits' along the diameter, while the
  /// damage before the peak can be diffuse in both), but at least a
  /// split's worth, n_grains^((dim-1)/dim) (a diametral line or plane
  /// breaks about one contact per grain it crosses), or all of them: a
  /// split formed mostly before the peak may need only a few more cracks
  /// to open. 0 when no crack formed after the peak (no failure).
  std::size_t brazilian_failure_cracks(std::size_t n_peak, std::size_t n_end,
                                       std::size_t n_grains, int dim);
} // namespace demfem::dem
