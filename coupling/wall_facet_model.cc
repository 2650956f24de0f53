#include "coupling/wall_facet_model.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace demfem::coupling
{
  using dem::Vec;

  std::vector<dealii::Point<2>> WallFacetModel::build_interface(std::ostream *progress)
  {
    // Ring of facets over the continuum's interface vertices, in angular
    // order; the coupling nodes are these vertices.
    const auto               pts = continuum().interface_vertices();
    std::vector<std::size_t> order(pts.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](auto a, auto b) {
      return std::atan2(pts[a][1], pts[a][0]) < std::atan2(pts[b][1], pts[b][0]);
    });
    wall_id = dem.walls.add_wall("interface");
    ring_vertex.assign(pts.size(), -1);
    X0.resize(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k)
      X0[k] = Vec<2>(pts[k][0], pts[k][1]);
    for (auto k : order)
      ring_vertex[k] = dem.walls.add_vertex(X0[k]);
    for (std::size_t a = 0; a < order.size(); ++a)
      dem.walls.add_facet(
          wall_id, {ring_vertex[order[a]], ring_vertex[order[(a + 1) % order.size()]]});
    groups = build_disk_region(dem, rp, progress);
    return pts;
  }

  Vec<2> WallFacetModel::gather_forces(std::vector<Vec<2>> &nodal) const
  {
    for (std::size_t k = 0; k < X0.size(); ++k)
      nodal[k] += dem.walls.vertex_force[ring_vertex[k]];
    // DEM side of the balance, independent of the vertex distribution: the
    // forces on the wall ends of the ring contacts.
    Vec<2> sum = Vec<2>::Zero();
    for (int g = 0; g < dem.n_groups(); ++g)
      {
        const auto &grp = dem.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (grp.is_wall[k] && dem.walls.facet_wall[grp.end2[k]] == wall_id)
            sum += grp.force[k];
      }
    return sum;
  }

  void WallFacetModel::move_interface(const std::vector<Vec<2>> &u,
                                      const std::vector<Vec<2>> &v)
  {
    for (std::size_t k = 0; k < X0.size(); ++k)
      {
        // Positions re-synchronized (round-off only), then the vertices move
        // with v over the next window.
        dem.walls.vertex[ring_vertex[k]]          = X0[k] + u[k];
        dem.walls.vertex_velocity[ring_vertex[k]] = v[k];
      }
  }
} // namespace demfem::coupling
