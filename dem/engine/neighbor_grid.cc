#include "dem/engine/neighbor_grid.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem
{
  template <int dim>
  std::int64_t NeighborGrid<dim>::cell_of(const Vec<dim> &x) const
  {
    std::int64_t c = 0, stride = 1;
    for (int d = 0; d < dim; ++d)
      {
        std::int64_t k = static_cast<std::int64_t>(std::floor((x[d] - lo_[d]) / h_));
        k              = std::clamp<std::int64_t>(k, 0, n_[d] - 1);
        c += k * stride;
        stride *= n_[d];
      }
    return c;
  }

  template <int dim>
  void NeighborGrid<dim>::bin(const Particles<dim> &p, double skin)
  {
    const std::size_t N = p.size();
    Vec<dim>          hi;
    lo_.setConstant(HUGE_VAL);
    hi.setConstant(-HUGE_VAL);
    for (std::size_t i = 0; i < N; ++i)
      {
        lo_ = lo_.cwiseMin(p.x[i]);
        hi  = hi.cwiseMax(p.x[i]);
      }
    if (N == 0)
      lo_.setZero(), hi.setZero();
    h_ = std::max(2 * p.max_radius() + skin, 1e-300);
    // Bound the number of cells by ~2N so sparse domains stay O(N) in memory.
    std::int64_t total = 1;
    for (int d = 0; d < dim; ++d)
      {
        n_[d] = std::max<std::int64_t>(1, static_cast<std::int64_t>((hi[d] - lo_[d]) / h_) + 1);
        total *= n_[d];
      }
    while (total > 2 * static_cast<std::int64_t>(N) + 8)
      {
        h_ *= 1.25;
        total = 1;
        for (int d = 0; d < dim; ++d)
          {
            n_[d] = std::max<std::int64_t>(1, static_cast<std::int64_t>((hi[d] - lo_[d]) / h_) + 1);
            total *= n_[d];
          }
      }
    // Counting sort of the particles by cell.
    cell_start_.assign(total + 1, 0);
    std::vector<std::int64_t> cell(N);
    for (std::size_t i = 0; i < N; ++i)
      {
        cell[i] = cell_of(p.x[i]);
        ++cell_start_[cell[i] + 1];
      }
    for (std::int64_t c = 0; c < total; ++c)
      cell_start_[c + 1] += cell_start_[c];
    sorted_.resize(N);
    std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < N; ++i)
      sorted_[fill[cell[i]]++] = static_cast<std::uint32_t>(i);
  }

  template <int dim>
  std::vector<std::pair<std::uint32_t, std::uint32_t>>
  NeighborGrid<dim>::ball_pairs(const Particles<dim> &p, double skin)
  {
    bin(p, skin);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    pairs.reserve(4 * p.size());
    const std::int64_t nz = dim == 3 ? n_[2] : 1;
    for (std::int64_t cz = 0; cz < nz; ++cz)
      for (std::int64_t cy = 0; cy < n_[1]; ++cy)
        for (std::int64_t cx = 0; cx < n_[0]; ++cx)
          {
            const std::int64_t c = cx + n_[0] * (cy + n_[1] * cz);
            for (std::int64_t dz = (dim == 3 ? -1 : 0); dz <= (dim == 3 ? 1 : 0); ++dz)
              for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dx = -1; dx <= 1; ++dx)
                  {
                    const std::int64_t x = cx + dx, y = cy + dy, z = cz + dz;
                    if (x < 0 || y < 0 || z < 0 || x >= n_[0] || y >= n_[1] || z >= nz)
                      continue;
                    const std::int64_t o = x + n_[0] * (y + n_[1] * z);
                    if (o < c)
                      continue; // each cell pair once
                    for (std::uint32_t a = cell_start_[c]; a < cell_start_[c + 1]; ++a)
                      for (std::uint32_t b = (o == c ? a + 1 : cell_start_[o]); b < cell_start_[o + 1]; ++b)
                        {
                          std::uint32_t i = sorted_[a], j = sorted_[b];
                          const double  reach = p.radius[i] + p.radius[j] + skin;
                          if ((p.x[j] - p.x[i]).squaredNorm() < reach * reach)
                            pairs.emplace_back(std::min(i, j), std::max(i, j));
                        }
                  }
          }
    std::sort(pairs.begin(), pairs.end());
    return pairs;
  }

  template <int dim>
  std::vector<std::pair<std::uint32_t, std::uint32_t>>
  NeighborGrid<dim>::wall_pairs(const Particles<dim> &p, const Walls<dim> &w, double skin)
  {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    if (w.n_facets() == 0 || p.size() == 0)
      return pairs;
    bin(p, skin);
    const double reach = p.max_radius() + skin;
    for (std::size_t k = 0; k < w.n_facets(); ++k)
      {
        // Cells overlapped by the facet's bounding box grown by the reach.
        Vec<dim> blo = w.vertex[w.facet[k][0]], bhi = blo;
        for (int v : w.facet[k])
          blo = blo.cwiseMin(w.vertex[v]), bhi = bhi.cwiseMax(w.vertex[v]);
        std::array<std::int64_t, 3> a{0, 0, 0}, b{0, 0, 0};
        bool                        outside = false;
        for (int d = 0; d < dim; ++d)
          {
            a[d] = static_cast<std::int64_t>(std::floor((blo[d] - reach - lo_[d]) / h_));
            b[d] = static_cast<std::int64_t>(std::floor((bhi[d] + reach - lo_[d]) / h_));
            if (b[d] < 0 || a[d] >= n_[d])
              outside = true;
            a[d] = std::max<std::int64_t>(a[d], 0);
            b[d] = std::min<std::int64_t>(b[d], n_[d] - 1);
          }
        if (outside)
          continue;
        std::array<double, dim> wgt;
        for (std::int64_t z = a[2]; z <= b[2]; ++z)
          for (std::int64_t y = a[1]; y <= b[1]; ++y)
            for (std::int64_t x = a[0]; x <= b[0]; ++x)
              {
                const std::int64_t c = x + n_[0] * (y + n_[1] * z);
                for (std::uint32_t s = cell_start_[c]; s < cell_start_[c + 1]; ++s)
                  {
                    const std::uint32_t i  = sorted_[s];
                    const Vec<dim>      cp = w.closest_point(k, p.x[i], wgt);
                    const double        r  = p.radius[i] + skin;
                    if ((cp - p.x[i]).squaredNorm() < r * r)
                      pairs.emplace_back(i, static_cast<std::uint32_t>(k));
                  }
              }
      }
    std::sort(pairs.begin(), pairs.end());
    return pairs;
  }

  template class NeighborGrid<2>;
  template class NeighborGrid<3>;
} // namespace demfem::dem
