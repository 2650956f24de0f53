#include "coupling/wall_facet_model.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace demfem::coupling
{
  using dem::Vec;

  template <int dim>
  std::vector<dealii::Point<dim>> WallFacetModel<dim>::build_interface(
      std::ostream *progress)
  {
    // Ring of facets over the continuum's interface vertices, in angular
    // order (3D: by z level, then angle); the coupling nodes are these
    // vertices.
    const auto               pts = this->continuum().interface_vertices();
    std::vector<std::size_t> order(pts.size());
    std::iota(order.begin(), order.end(), 0);
    const double tol = 1e-9 * rp.radius;
    std::sort(order.begin(), order.end(), [&](auto a, auto b) {
      if constexpr (dim == 3)
        if (std::abs(pts[a][2] - pts[b][2]) > tol)
          return pts[a][2] < pts[b][2];
      return std::atan2(pts[a][1], pts[a][0]) < std::atan2(pts[b][1], pts[b][0]);
    });
    wall_id = dem.walls.add_wall("interface");
    ring_vertex.assign(pts.size(), -1);
    X0.resize(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k)
      for (int c = 0; c < dim; ++c)
        X0[k][c] = pts[k][c];
    for (auto k : order)
      ring_vertex[k] = dem.walls.add_vertex(X0[k]);
    if constexpr (dim == 2)
      for (std::size_t a = 0; a < order.size(); ++a)
        dem.walls.add_facet(wall_id, {{ring_vertex[order[a]],
                                       ring_vertex[order[(a + 1) % order.size()]]}});
    else
      {
        // Levels of n vertices each (the mesh's z layers); quad (k, l) ->
        // two triangles, as add_cylinder_ring.
        std::size_t n = 0;
        while (n < order.size() && std::abs(pts[order[n]][2] - pts[order[0]][2]) <= tol)
          ++n;
        if (n < 3 || order.size() % n != 0)
          throw std::runtime_error("wall facets: the interface vertices are not " +
                                   std::string("levels of equal size in z"));
        const std::size_t levels = order.size() / n;
        auto              vtx    = [&](std::size_t l, std::size_t k) {
          return ring_vertex[order[l * n + k % n]];
        };
        for (std::size_t l = 0; l + 1 < levels; ++l)
          for (std::size_t k = 0; k < n; ++k)
            {
              const int a = vtx(l, k), b = vtx(l, k + 1), c = vtx(l + 1, k + 1),
                        d = vtx(l + 1, k);
              dem.walls.add_facet(wall_id, {{a, b, c}});
              dem.walls.add_facet(wall_id, {{a, c, d}});
            }
      }
    groups = build_region<dim>(dem, rp, progress);
    return pts;
  }

  template <int dim>
  Vec<dim> WallFacetModel<dim>::gather_forces(std::vector<Vec<dim>> &nodal) const
  {
    for (std::size_t k = 0; k < X0.size(); ++k)
      nodal[k] += dem.walls.vertex_force[ring_vertex[k]];
    // DEM side of the balance, independent of the vertex distribution: the
    // forces on the wall ends of the ring contacts.
    Vec<dim> sum = Vec<dim>::Zero();
    for (int g = 0; g < dem.n_groups(); ++g)
      {
        const auto &grp = dem.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (grp.is_wall[k] && dem.walls.facet_wall[grp.end2[k]] == wall_id)
            sum += grp.force[k];
      }
    return sum;
  }

  template <int dim>
  void WallFacetModel<dim>::move_interface(const std::vector<Vec<dim>> &u,
                                           const std::vector<Vec<dim>> &v)
  {
    for (std::size_t k = 0; k < X0.size(); ++k)
      {
        // Positions re-synchronized (round-off only), then the vertices move
        // with v over the next window.
        dem.walls.vertex[ring_vertex[k]]          = X0[k] + u[k];
        dem.walls.vertex_velocity[ring_vertex[k]] = v[k];
      }
  }

  template class WallFacetModel<2>;
  template class WallFacetModel<3>;
} // namespace demfem::coupling
