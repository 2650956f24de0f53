// Failure mode of the Brazilian test (see brazilian_failure.h).
#include "dem/specimen/brazilian_failure.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem
{
  template <int dim>
  BrazilianFailure classify_brazilian_failure(const std::vector<Vec<dim>> &positions,
                                              const Vec<dim> &centre, const double R,
                                              const double threshold)
  {
    BrazilianFailure f;
    f.cracks = positions.size();
    if (positions.empty())
      {
        f.mode = "no_failure";
        return f;
      }
    constexpr int ax = dim - 1; // loading axis (fistPkg Fig. 29)
    for (const auto &p : positions)
      if (std::abs(p[0] - centre[0]) < split_zone_half_width * R &&
          std::abs(p[ax] - centre[ax]) < split_zone_half_length * R)
        ++f.in_zone;
    f.fraction = double(f.in_zone) / double(f.cracks);
    f.mode     = f.fraction >= threshold ? "split" : "not_split";
    return f;
  }

  std::size_t brazilian_failure_cracks(const std::size_t n_peak, const std::size_t n_end,
                                       const std::size_t n_grains, const int dim)
  {
    if (n_end <= n_peak)
      return 0;
    const auto split = static_cast<std::size_t>(
        std::ceil(std::pow(double(n_grains), (dim - 1.0) / dim)));
    return std::max(n_end - n_peak, std::min(n_end, split));
  }

  template BrazilianFailure classify_brazilian_failure<2>(const std::vector<Vec<2>> &,
                                                          const Vec<2> &, double, double);
  template BrazilianFailure classify_brazilian_failure<3>(const std::vector<Vec<3>> &,
                                                          const Vec<3> &, double, double);
} // namespace demfem::dem
