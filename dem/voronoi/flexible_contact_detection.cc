// New contacts of the flexible Voronoi model under large displacements
// (seed 004 §2; dem/voronoi/flexible_model.h; docs/voronoi.md, "New
// contacts").
//
// Search: a Verlet list. At a rebuild the current disk centres go into a
// uniform grid of cells no smaller than the largest disk diameter plus the
// skin, so every pair within r_a + r_b + skin lies in the same or adjacent
// grid cells; those pairs not in contact yet are the candidates. Until some
// disk has moved more than half the skin since the rebuild, no other pair
// can come within r_a + r_b (each disk of the pair moved less than skin /
// 2), so each step only tests the candidates: O(N) for the displacement
// check plus O(candidates), no allocation. Everything is serial and in
// ascending (a, b) order, so the contacts, their point order and the gather
// lists do not depend on the thread count.
#include "dem/voronoi/flexible_model.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem::voronoi
{
  namespace
  {
    /// Squared distance from (px, py) to the segment (ax, ay)-(bx, by).
    double segment_distance2(double px, double py, double ax, double ay, double bx,
                             double by)
    {
      const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
      double       u  = l2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / l2 : 0.0;
      u               = std::clamp(u, 0.0, 1.0);
      const double ex = ax + u * dx - px, ey = ay + u * dy - py;
      return ex * ex + ey * ey;
    }
  } // namespace

  bool FlexibleVoronoiModel::in_contact(int a, int b) const
  {
    const std::int64_t key = std::int64_t(std::min(a, b)) * n_grains() + std::max(a, b);
    return std::binary_search(contact_keys.begin(), contact_keys.end(), key);
  }

  void FlexibleVoronoiModel::rebuild_verlet_list()
  {
    ++n_verlet_rebuilds;
    const int ng = n_grains();
    verlet_x.assign(ng, 0.0);
    verlet_y.assign(ng, 0.0);
    candidates.clear();
    candidate_done.clear();
    // Grains of empty cells have no nodes and no disk in the model.
    auto meshed = [&](int c) {
      return mesh.grain_triangle_offset[c + 1] > mesh.grain_triangle_offset[c];
    };
    double rmax = 0, xmin = HUGE_VAL, ymin = HUGE_VAL, xmax = -HUGE_VAL, ymax = -HUGE_VAL;
    for (int c = 0; c < ng; ++c)
      if (meshed(c))
        {
          verlet_x[c] = disk_x(c);
          verlet_y[c] = disk_y(c);
          rmax        = std::max(rmax, disk_radius[c]);
          xmin        = std::min(xmin, verlet_x[c]);
          xmax        = std::max(xmax, verlet_x[c]);
          ymin        = std::min(ymin, verlet_y[c]);
          ymax        = std::max(ymax, verlet_y[c]);
        }
    verlet_skin = verlet_skin_fraction * rmax;
    if (!(rmax > 0))
      return; // no disk can overlap another
    // A diverged run (non-finite positions) gets no new contacts rather than
    // a grid it cannot size; its NaNs propagate as without the search.
    if (!std::isfinite(xmax - xmin) || !std::isfinite(ymax - ymin))
      return;
    // Grid cell >= the largest disk diameter plus the skin; at most ~4 grid
    // cells per grain (grains flung far apart enlarge the cells instead of
    // the grid).
    double    h  = 2 * rmax + verlet_skin;
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
      if (meshed(c))
        {
          cell_of(c, i, j);
          ++grid_start[j * nx + i + 1];
        }
    for (int k = 0; k < nx * ny; ++k)
      grid_start[k + 1] += grid_start[k];
    {
      // Fill in ascending grain order (a counting sort; deterministic).
      std::vector<int> fill(grid_start.begin(), grid_start.end() - 1);
      for (int c = 0; c < ng; ++c)
        if (meshed(c))
          {
            cell_of(c, i, j);
            grid_item[fill[j * nx + i]++] = c;
          }
    }
    for (int a = 0; a < ng; ++a)
      {
        if (!meshed(a))
          continue;
        cell_of(a, i, j);
        for (int jj = std::max(0, j - 1); jj <= std::min(ny - 1, j + 1); ++jj)
          for (int ii = std::max(0, i - 1); ii <= std::min(nx - 1, i + 1); ++ii)
            for (int q = grid_start[jj * nx + ii]; q < grid_start[jj * nx + ii + 1]; ++q)
              {
                const int b = grid_item[q];
                if (b <= a)
                  continue;
                const double reach = disk_radius[a] + disk_radius[b] + verlet_skin;
                const double dx    = verlet_x[b] - verlet_x[a],
                             dy    = verlet_y[b] - verlet_y[a];
                if (dx * dx + dy * dy < reach * reach && !in_contact(a, b))
                  candidates.emplace_back(a, b);
              }
      }
    std::sort(candidates.begin(), candidates.end());
    candidate_done.assign(candidates.size(), 0);
  }

  int FlexibleVoronoiModel::detect_new_contacts(double dt)
  {
    // Rebuild when some disk has moved more than half the skin.
    const int    ng    = n_grains();
    const double limit = 0.25 * verlet_skin * verlet_skin;
    bool         stale = false;
    for (int c = 0; c < ng && !stale; ++c)
      if (mesh.grain_triangle_offset[c + 1] > mesh.grain_triangle_offset[c])
        {
          const double dx = disk_x(c) - verlet_x[c], dy = disk_y(c) - verlet_y[c];
          stale = dx * dx + dy * dy > limit;
        }
    if (stale)
      rebuild_verlet_list();
    const int formed = form_new_contacts(false, dt);
    if (formed > 0)
      build_gather_lists();
    return formed;
  }

  int FlexibleVoronoiModel::form_new_contacts(bool at_install, double dt)
  {
    int formed = 0;
    for (std::size_t k = 0; k < candidates.size(); ++k)
      {
        if (candidate_done[k])
          continue;
        const int    a = candidates[k].first, b = candidates[k].second;
        const double dx = disk_x(b) - disk_x(a), dy = disk_y(b) - disk_y(a);
        const double reach = disk_radius[a] + disk_radius[b];
        if (dx * dx + dy * dy < reach * reach)
          {
            form_contact(a, b, at_install, dt);
            candidate_done[k] = 1;
            ++formed;
          }
      }
    return formed;
  }

  void FlexibleVoronoiModel::form_contact(int a, int b, bool at_install, double dt)
  {
    const double xa = disk_x(a), ya = disk_y(a), xb = disk_x(b), yb = disk_y(b);
    const double ra = disk_radius[a], rb = disk_radius[b];
    const double dist = std::hypot(xb - xa, yb - ya);
    const double nx = (xb - xa) / dist, ny = (yb - ya) / dist, tx = -ny, ty = nx;
    const double U = ra + rb - dist; // > 0: the disks overlap
    // Reference point: the PCM contact point x_A + (R_A - U/2) n (delta = 0;
    // seed 004's reference point with no cell edge shared at install).
    const double xr = xa + (ra - U / 2) * nx, yr = ya + (ra - U / 2) * ny;
    // Seed 004 §2: in each grain the Voronoi edge closest to the contact
    // location; the cell's edges are the boundary segments (node 1, node 2)
    // of its fan triangles in the current mesh (merged short edges included).
    auto nearest_edge_length = [&](int g) {
      double best = HUGE_VAL, length = 0;
      for (int t = mesh.grain_triangle_offset[g]; t < mesh.grain_triangle_offset[g + 1];
           ++t)
        {
          const int p     = mesh.triangle_nodes[3 * t + 1],
                    q     = mesh.triangle_nodes[3 * t + 2];
          const double d2 = segment_distance2(xr, yr, x[p], y[p], x[q], y[q]);
          if (d2 < best)
            {
              best   = d2;
              length = std::hypot(x[q] - x[p], y[q] - y[p]);
            }
        }
      return length;
    };
    // Contact length: the shorter of the two selected edges (docs/voronoi.md,
    // "New contacts"). The two faces can be in contact over no more than the
    // shorter one; on the line of centres the contact (the DEM criterion)
    // need not lie where two cells that were never neighbours face each
    // other, so the projected overlap of the edges could be empty or
    // degenerate while the disks overlap, whereas the shorter edge is always
    // a positive length of the grains' own scale. Centred on the reference
    // point, the points' forces have no moment about it at formation (the
    // PCM force), and for two cells pressed face to face it is the length
    // of the face they share.
    const double L = std::min(nearest_edge_length(a), nearest_edge_length(b));
    const int    k = contacts.add_contact(a, b, xa, ya, ra, xb, yb, rb, xr - 0.5 * L * tx,
                                          yr - 0.5 * L * ty, xr + 0.5 * L * tx,
                                          yr + 0.5 * L * ty, scheme);
    contacts.offset[k] = 0; // the PCM plane itself, not roundoff of it
    for (int p = contacts.point_offset[k]; p < contacts.point_offset[k + 1]; ++p)
      {
        // Unbonded: a contact between separate grains carries friction
        // only. Its normal displacement is measured from the touching
        // disks (u_n = -U now), so the force is kn A_i times the overlap,
        // the DEM law the seed keeps; at install it starts stress free.
        const double X = xr + contacts.s[p] * tx, Y = yr + contacts.s[p] * ty;
        const int    ta = mesh.locate(a, x.data(), y.data(), X, Y);
        const int    tb = mesh.locate(b, x.data(), y.data(), X, Y);
        triangle_a.push_back(ta);
        triangle_b.push_back(tb);
        contacts.crack[p] = PointCrack::unbonded;
        // The positions already hold the last velocity increment (central
        // differences: x^n = x^(n-1) + dt v^(n-1/2)), and update_contact_
        // points adds dt v^(n-1/2) . n once more in this step: subtract it
        // here, with the same arithmetic, so that u_n = -U after the update.
        double Na[3], Nb[3], vrx = 0, vry = 0;
        mesh.shape_functions(ta, x.data(), y.data(), X, Y, Na);
        mesh.shape_functions(tb, x.data(), y.data(), X, Y, Nb);
        for (int i = 0; i < 3; ++i)
          {
            const int ma = mesh.triangle_nodes[3 * ta + i],
                      mb = mesh.triangle_nodes[3 * tb + i];
            vrx += Nb[i] * vx[mb] - Na[i] * vx[ma];
            vry += Nb[i] * vy[mb] - Na[i] * vy[ma];
          }
        contacts.un[p] = at_install ? 0.0 : -U - (vrx * nx + vry * ny) * dt;
      }
    const int np = contacts.n_points();
    point_fx.resize(np, 0.0);
    point_fy.resize(np, 0.0);
    point_N.resize(6 * np, 0.0);
    contact_keys.insert(std::upper_bound(contact_keys.begin(), contact_keys.end(),
                                         std::int64_t(a) * n_grains() + b),
                        std::int64_t(a) * n_grains() + b);
  }
} // namespace demfem::dem::voronoi
