// Crack initiation from the crack volumetric strain or the lateral strain
// response, and crack damage (dem/specimen/crack_initiation.h).
#include "dem/specimen/crack_initiation.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem
{
  std::size_t crack_volumetric_initiation_row(const CompressionBranch &b, double E,
                                              double nu, int lateral_directions,
                                              double fit_lo, double fit_hi,
                                              double fraction)
  {
    const std::size_t n = b.volumetric_strain.size();
    if (n == 0 || b.axial_stress.size() != n || b.load.size() != n || b.peak_row >= n ||
        !(E > 0) || !std::isfinite(nu))
      return n;
    auto cv = [&](std::size_t i) {
      return (b.volumetric_strain[i] - b.volumetric_strain[0]) -
             (1 - lateral_directions * nu) * (b.axial_stress[i] - b.axial_stress[0]) / E;
    };
    const double peak_load = b.load[b.peak_row];
    double       zero      = 0;
    int          in_window = 0;
    for (std::size_t i = 0; i <= b.peak_row; ++i)
      if (b.load[i] >= fit_lo * peak_load && b.load[i] <= fit_hi * peak_load)
        zero += cv(i), ++in_window;
    if (in_window == 0)
      return n;
    zero /= in_window;
    // The scale of "zero": the elastic volumetric strain at the peak (the
    // rise of the crack volumetric strain itself can be tens of times
    // larger, so a fraction of it would read a late onset).
    const double elastic_at_peak =
        std::abs((1 - lateral_directions * nu) *
                 (b.axial_stress[b.peak_row] - b.axial_stress[0]) / E);
    const double threshold = fraction * elastic_at_peak;
    if (!(cv(b.peak_row) - zero > threshold)) // never left zero before the peak
      return n;
    std::size_t last_flat = 0;
    for (std::size_t i = 0; i <= b.peak_row; ++i)
      if (cv(i) - zero <= threshold)
        last_flat = i;
    return std::min(last_flat + 1, b.peak_row);
  }

  std::size_t volumetric_reversal_row(const CompressionBranch &b)
  {
    const std::size_t n = b.volumetric_strain.size();
    if (n == 0 || b.peak_row >= n)
      return n;
    std::size_t min = 0;
    for (std::size_t i = 1; i <= b.peak_row; ++i)
      if (b.volumetric_strain[i] < b.volumetric_strain[min])
        min = i;
    return min < b.peak_row ? min : n;
  }

  std::size_t lateral_strain_initiation_row(const CompressionBranch &b,
                                            const std::size_t        damage_row)
  {
    const std::size_t n = b.axial_stress.size();
    if (b.lateral_strain.size() != n || damage_row == 0 || damage_row >= n ||
        damage_row > b.peak_row)
      return n;
    auto stress = [&](std::size_t i) {
      return std::abs(b.axial_stress[i] - b.axial_stress[0]);
    };
    auto lateral = [&](std::size_t i) {
      return b.lateral_strain[i] - b.lateral_strain[0];
    };
    const double s_damage = stress(damage_row), e_damage = lateral(damage_row);
    if (!(s_damage > 0) || !(e_damage > 0)) // tension positive: expansion > 0
      return n;
    // Distance of the lateral strain below the reference line (the secant
    // to crack damage); it grows while the tangent slope is below the
    // secant's and shrinks after: its largest value marks the onset.
    std::size_t best = n;
    // A straight lateral strain lies on the line to rounding (1e-16 of its
    // value): below 1e-12 of it there is no departure to read.
    double largest = 1e-12 * e_damage;
    for (std::size_t i = 1; i < damage_row; ++i)
      {
        const double below = e_damage * stress(i) / s_damage - lateral(i);
        if (below > largest)
          largest = below, best = i;
      }
    return best;
  }
} // namespace demfem::dem
