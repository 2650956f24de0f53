// Search for new contacts between Voronoi grains
// (dem/voronoi/new_contact_search.h; docs/voronoi.md, "New contacts").
#include "dem/voronoi/new_contact_search.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem::voronoi
{
  double segment_distance2(double px, double py, double ax, double ay, double bx,
                           double by)
  {
    const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
    double       u  = l2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / l2 : 0.0;
    u               = std::clamp(u, 0.0, 1.0);
    const double ex = ax + u * dx - px, ey = ay + u * dy - py;
    return ex * ex + ey * ey;
  }

  void NewContactSearch::reset(int n_grains)
  {
    n = n_grains;
    keys.clear();
    candidate.clear();
    candidate_done.clear();
    found.clear();
    verlet_x.assign(n, 0.0);
    verlet_y.assign(n, 0.0);
    skin_ = 0;
  }

  void NewContactSearch::add_contact(int a, int b)
  {
    const std::int64_t key = std::int64_t(std::min(a, b)) * n + std::max(a, b);
    const auto         it  = std::lower_bound(keys.begin(), keys.end(), key);
    if (it == keys.end() || *it != key)
      keys.insert(it, key);
  }

  bool NewContactSearch::in_contact(int a, int b) const
  {
    const std::int64_t key = std::int64_t(std::min(a, b)) * n + std::max(a, b);
    return std::binary_search(keys.begin(), keys.end(), key);
  }

  void NewContactSearch::rebuild(const double *x, const double *y, const double *r,
                                 const char *active, double skin_fraction)
  {
    const int ng = n;
    verlet_x.assign(ng, 0.0);
    verlet_y.assign(ng, 0.0);
    candidate.clear();
    candidate_done.clear();
    double rmax = 0, xmin = HUGE_VAL, ymin = HUGE_VAL, xmax = -HUGE_VAL, ymax = -HUGE_VAL;
    for (int c = 0; c < ng; ++c)
      if (active[c])
        {
          verlet_x[c] = x[c];
          verlet_y[c] = y[c];
          rmax        = std::max(rmax, r[c]);
          xmin        = std::min(xmin, verlet_x[c]);
          xmax        = std::max(xmax, verlet_x[c]);
          ymin        = std::min(ymin, verlet_y[c]);
          ymax        = std::max(ymax, verlet_y[c]);
        }
    skin_ = skin_fraction * rmax;
    if (!(rmax > 0))
      return; // no disk can overlap another
    // A diverged run (non-finite positions) gets no new contacts rather than
    // a grid it cannot size; its NaNs propagate as without the search.
    if (!std::isfinite(xmax - xmin) || !std::isfinite(ymax - ymin))
      return;
    // Grid cell >= the largest disk diameter plus the skin; at most ~4 grid
    // cells per grain (grains flung far apart enlarge the cells instead of
    // the grid).
    double    h  = 2 * rmax + skin_;
    const int nc = std::max(16, 4 * ng);
    int       nx = 1, ny = 1;
    for (;;)
      {
        nx = static_cast<int>(std::min(1e9, std::floor((xmax - xmin) / h))) + 1;
        ny = static_cast<int>(std::min(1e9, std::floor((ymax - ymin) / h))) + 1;
        if (double(nx) * ny <= nc)
          break;
        h *= 2;
      }
    auto cell_of = [&](int c, int &i, int &j) {
      i = std::min(nx - 1, static_cast<int>((verlet_x[c] - xmin) / h));
      j = std::min(ny - 1, static_cast<int>((verlet_y[c] - ymin) / h));
    };
    grid_start.assign(nx * ny + 1, 0);
    grid_item.resize(ng);
    int i, j;
    for (int c = 0; c < ng; ++c)
      if (active[c])
        {
          cell_of(c, i, j);
          ++grid_start[j * nx + i + 1];
        }
    for (int k = 0; k < nx * ny; ++k)
      grid_start[k + 1] += grid_start[k];
    // Fill in ascending grain order (a counting sort; deterministic).
    grid_fill.assign(grid_start.begin(), grid_start.end() - 1);
    for (int c = 0; c < ng; ++c)
      if (active[c])
        {
          cell_of(c, i, j);
          grid_item[grid_fill[j * nx + i]++] = c;
        }
    for (int a = 0; a < ng; ++a)
      {
        if (!active[a])
          continue;
        cell_of(a, i, j);
        for (int jj = std::max(0, j - 1); jj <= std::min(ny - 1, j + 1); ++jj)
          for (int ii = std::max(0, i - 1); ii <= std::min(nx - 1, i + 1); ++ii)
            for (int q = grid_start[jj * nx + ii]; q < grid_start[jj * nx + ii + 1]; ++q)
              {
                const int b = grid_item[q];
                if (b <= a)
                  continue;
                const double reach = r[a] + r[b] + skin_;
                const double dx    = verlet_x[b] - verlet_x[a],
                             dy    = verlet_y[b] - verlet_y[a];
                if (dx * dx + dy * dy < reach * reach && !in_contact(a, b))
                  candidate.emplace_back(a, b);
              }
      }
    std::sort(candidate.begin(), candidate.end());
    candidate_done.assign(candidate.size(), 0);
  }

  bool NewContactSearch::stale(const double *x, const double *y, const char *active) const
  {
    const double limit = 0.25 * skin_ * skin_;
    for (int c = 0; c < n; ++c)
      if (active[c])
        {
          const double dx = x[c] - verlet_x[c], dy = y[c] - verlet_y[c];
          if (dx * dx + dy * dy > limit)
            return true;
        }
    return false;
  }

  const std::vector<std::pair<int, int>> &NewContactSearch::new_overlaps(const double *x,
                                                                         const double *y,
                                                                         const double *r)
  {
    found.clear();
    for (std::size_t k = 0; k < candidate.size(); ++k)
      {
        if (candidate_done[k])
          continue;
        const int    a = candidate[k].first, b = candidate[k].second;
        const double dx = x[b] - x[a], dy = y[b] - y[a];
        const double reach = r[a] + r[b];
        if (dx * dx + dy * dy < reach * reach)
          {
            candidate_done[k] = 1;
            found.emplace_back(a, b);
            add_contact(a, b);
          }
      }
    return found;
  }
} // namespace demfem::dem::voronoi
