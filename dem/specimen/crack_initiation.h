#pragma once
// Crack-initiation stress from the crack volumetric strain of a
// compression test (Martin & Chandler 1994; docs/calibrate.md, "Crack
// initiation and crack damage"). Used by the bonded-particle lab tests
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
} // namespace demfem::dem
