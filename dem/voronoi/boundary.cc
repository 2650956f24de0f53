// Boundary conditions of a rectangular Voronoi specimen (dem/voronoi/boundary.h).
#include "dem/voronoi/boundary.h"

#include "dem/engine/types.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem::voronoi
{
  std::vector<SideEdge> rectangle_side_edges(const Tessellation &tess, double &xmin,
                                             double &ymin, double &xmax, double &ymax)
  {
    std::vector<SideEdge> out;
    xmin = ymin = xmax = ymax = 0;
    if (tess.vertex_x.empty())
      return out;
    xmin = *std::min_element(tess.vertex_x.begin(), tess.vertex_x.end());
    xmax = *std::max_element(tess.vertex_x.begin(), tess.vertex_x.end());
    ymin = *std::min_element(tess.vertex_y.begin(), tess.vertex_y.end());
    ymax = *std::max_element(tess.vertex_y.begin(), tess.vertex_y.end());
    // The clipped vertices lie on the sides to roundoff of the clipping.
    const double tol = 1e-9 * std::hypot(xmax - xmin, ymax - ymin);
    for (int c = 0; c < tess.n_cells(); ++c)
      for (int e = tess.begin(c); e < tess.end(c); ++e)
        {
          if (tess.edge_neighbour[e] != Tessellation::boundary)
            continue;
          const int    f  = tess.next(c, e);
          const double ax = tess.vertex_x[e], ay = tess.vertex_y[e];
          const double bx = tess.vertex_x[f], by = tess.vertex_y[f];
          auto         on = [&](double u, double v, double w) {
            return std::abs(u - w) <= tol && std::abs(v - w) <= tol;
          };
          SideEdge s{c, e, Side::bottom};
          if (on(ay, by, ymin))
            s.side = Side::bottom;
          else if (on(ay, by, ymax))
            s.side = Side::top;
          else if (on(ax, bx, xmin))
            s.side = Side::left;
          else if (on(ax, bx, xmax))
            s.side = Side::right;
          else
            continue; // not on a rectangle side (circle domain)
          out.push_back(s);
        }
    return out;
  }

  Platen make_platen(Side side, PlatenLaw law, double friction)
  {
    if (side != Side::bottom && side != Side::top)
      throw InputError("Voronoi platen: platens are on the bottom or top side");
    check_range("Voronoi platen", "friction", friction, 0, HUGE_VAL, false, true);
    Platen p;
    p.side = side;
    p.law  = law;
    p.nx   = 0;
    p.ny   = side == Side::top ? 1.0 : -1.0;
    // Frictional platen: the law with no strength is the linear no-tension
    // Coulomb contact (dem/voronoi/softening_law.h); kn, ks are per point.
    ContactMaterial fm;
    fm.kn            = 1;
    fm.friction      = friction;
    p.frictional_law = SofteningCoefficients::derive(fm);
    return p;
  }
} // namespace demfem::dem::voronoi
