#pragma once
// Uniform cell grid for O(N) contact detection. Cells are at least one
// largest diameter plus the skin wide, so every pair closer than the skin is
// found in the 3^dim neighbourhood of a particle's cell.
#include "dem/engine/particles.h"
#include "dem/engine/walls.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace demfem::dem
{
  template <int dim>
  class NeighborGrid
  {
  public:
    /// All particle pairs (i < j) whose surface gap is below `skin`.
    std::vector<std::pair<std::uint32_t, std::uint32_t>>
    ball_pairs(const Particles<dim> &p, double skin);

    /// All (particle, facet) pairs whose gap (distance - radius) is below `skin`.
    std::vector<std::pair<std::uint32_t, std::uint32_t>>
    wall_pairs(const Particles<dim> &p, const Walls<dim> &w, double skin);

  private:
    void bin(const Particles<dim> &p, double skin);
    std::int64_t cell_of(const Vec<dim> &x) const;

    Vec<dim>                    lo_;
    double                      h_ = 1;
    std::array<std::int64_t, 3> n_{{1, 1, 1}};
    std::vector<std::uint32_t>  cell_start_; ///< CSR: particles sorted by cell
    std::vector<std::uint32_t>  sorted_;
  };
} // namespace demfem::dem
