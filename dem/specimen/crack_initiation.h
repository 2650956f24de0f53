#pragma once
// Crack-initiation stress of a compression test from the crack volumetric
// strain (Martin & Chandler 1994) or the lateral strain response (Nicksiar
// & Martin 2012), and the crack-damage row (volumetric strain reversal);
// docs/calibrate.md, "Crack initiation and crack damage". Used by the
// bonded-particle lab tests
// (dem/specimen/lab_tests.cc) and the Voronoi-grain ones
// (apps/calibrate_voronoi_run.cc), on their history rows.
#include <cstddef>
#include <vector>

namespace demfem::dem
{
  /// A compression test's loading branch, one entry per history row
  /// (tension positive), up to the peak at least.
  struct CompressionBranch
  {
    std::vector<double> volumetric_strain; ///< trace of the gauge strain
    std::vector<double> lateral_strain;    ///< mean lateral gauge strain
    std::vector<double> axial_stress;      ///< signed [Pa]
    std::vector<double> load;              ///< deviator magnitude [Pa]
    std::size_t         peak_row = 0;      ///< row of the largest load
  };

  /// The crack volumetric strain is the measured volumetric strain minus its
  /// elastic part, (1 - k nu) (sigma_a - sigma_a0) / E, from the loading
  /// branch's slopes E = d sigma_a / d eps_a, nu = -d eps_r / d eps_a (the
  /// lateral stress is held during loading: Pc or 0) with k the number of
  /// lateral directions (2D: 1, 3D: 2); strains from the first row. Its mean
  /// over the fit window [fit_lo, fit_hi] x peak load is its zero (the
  /// elastic part was fitted there). Crack initiation is the row after the
  /// last row up to the peak at which it is still within `fraction` of the
  /// elastic volumetric strain at the peak, |(1 - k nu) (sigma_a,peak -
  /// sigma_a0) / E|: from there on the specimen dilates for good, while a
  /// lone early crack that opens no volume does not count.
  /// Returns the row, or the number of rows if the method does not apply
  /// (E not positive, no row in the window, no dilatancy before the peak).
  std::size_t crack_volumetric_initiation_row(const CompressionBranch &branch, double E,
                                              double nu, int lateral_directions,
                                              double fit_lo, double fit_hi,
                                              double fraction);

  /// Crack damage: the row of the most compacted state (smallest
  /// volumetric strain) up to the peak, where crack dilatancy starts to
  /// outrun the elastic compaction (Martin & Chandler 1994). Returns the
  /// number of rows if the volume still shrinks at the peak (no reversal
  /// before it).
  std::size_t volumetric_reversal_row(const CompressionBranch &branch);

  /// Lateral strain response (Nicksiar & Martin 2012): the lateral strain
  /// against the axial stress increment |sigma_a - sigma_a0| is compared
  /// with the reference line from the first row to the crack-damage row
  /// `damage_row`; crack initiation is the row where the lateral strain lies
  /// farthest below that line, i.e. where its tangent slope reaches the
  /// line's secant slope: before it the specimen expands laterally at less
  /// than the average rate up to crack damage, after it at more. No
  /// threshold: a scale-free reading of the same onset the crack volumetric
  /// strain reads against a threshold. Returns the row, or the number of
  /// rows if it does not apply (no lateral_strain rows, damage_row not after
  /// the first row or past the peak, no lateral expansion at damage, or
  /// the lateral strain never below the line).
  std::size_t lateral_strain_initiation_row(const CompressionBranch &branch,
                                            std::size_t              damage_row);
} // namespace demfem::dem
