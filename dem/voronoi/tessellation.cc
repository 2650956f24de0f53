// Laguerre tessellation (dem/voronoi/tessellation.h). The only translation
// unit of demfem that includes CGAL (docs/voronoi.md, "Tessellation").
//
// Method. CGAL::Regular_triangulation_2 of the weighted points (p_i, R_i^2)
// is the dual of the power diagram: disk i has a non-empty power cell iff it
// is a (non-hidden) vertex, and cells i and j share an edge iff i-j is a
// triangulation edge. The power cell of a vertex i is therefore the
// intersection of the half-planes
//   |x - p_i|^2 - w_i <= |x - p_j|^2 - w_j   for the neighbours j of i,
// which is intersected with the (convex) clip polygon by clipping that
// polygon with each half-plane in turn. Each polygon edge remembers the
// half-plane (neighbour) or boundary that made it, which gives the shared
// edges. The clipping runs in coordinates relative to p_i, where the
// half-plane is 2 y.(p_j - p_i) <= |p_j - p_i|^2 + w_i - w_j, so the result
// does not lose digits to the distance of the packing from the origin.
#include "dem/voronoi/tessellation.h"

#include "dem/engine/types.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Regular_triangulation_face_base_2.h>
#include <CGAL/Regular_triangulation_vertex_base_2.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace demfem::dem::voronoi
{
  namespace
  {
    using Kernel     = CGAL::Exact_predicates_inexact_constructions_kernel;
    using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<
        int, Kernel, CGAL::Regular_triangulation_vertex_base_2<Kernel>>;
    using FaceBase  = CGAL::Regular_triangulation_face_base_2<Kernel>;
    using Tds       = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
    using Regular   = CGAL::Regular_triangulation_2<Kernel, Tds>;
    using WeightedP = Regular::Weighted_point;
    using BareP     = Regular::Bare_point;

    /// Convex polygon in coordinates relative to its disk centre; label[k]
    /// tags the edge from vertex k to vertex k+1.
    struct LabelledPolygon
    {
      std::vector<double> x, y;
      std::vector<int>    label;
      void                clear()
      {
        x.clear();
        y.clear();
        label.clear();
      }
      void push(double px, double py, int l)
      {
        x.push_back(px);
        y.push_back(py);
        label.push_back(l);
      }
      std::size_t size() const { return x.size(); }
    };

    /// Sutherland-Hodgman clip of a convex polygon by a x + b y <= c; the
    /// edge created along the line gets label `line_label`.
    void clip(const LabelledPolygon &in, double a, double b, double c, int line_label,
              LabelledPolygon &out)
    {
      out.clear();
      const std::size_t n = in.size();
      for (std::size_t k = 0; k < n; ++k)
        {
          const std::size_t m     = (k + 1) % n;
          const double      s_cur = a * in.x[k] + b * in.y[k] - c;
          const double      s_nxt = a * in.x[m] + b * in.y[m] - c;
          const bool        i_cur = s_cur <= 0, i_nxt = s_nxt <= 0;
          if (i_cur)
            out.push(in.x[k], in.y[k], in.label[k]);
          if (i_cur != i_nxt)
            {
              const double t  = s_cur / (s_cur - s_nxt);
              const double px = in.x[k] + t * (in.x[m] - in.x[k]);
              const double py = in.y[k] + t * (in.y[m] - in.y[k]);
              // Leaving the half-plane starts the new edge along the line;
              // entering it resumes the remainder of edge k.
              out.push(px, py, i_cur ? line_label : in.label[k]);
            }
        }
    }

    /// Removes edges shorter than tol (their start vertex and label).
    void drop_degenerate_edges(LabelledPolygon &p, double tol)
    {
      bool changed = true;
      while (changed && p.size() >= 3)
        {
          changed = false;
          for (std::size_t k = 0; k < p.size(); ++k)
            {
              const std::size_t m = (k + 1) % p.size();
              if (std::hypot(p.x[m] - p.x[k], p.y[m] - p.y[k]) < tol)
                {
                  p.x.erase(p.x.begin() + k);
                  p.y.erase(p.y.begin() + k);
                  p.label.erase(p.label.begin() + k);
                  changed = true;
                  break;
                }
            }
        }
    }
  } // namespace

  ClipDomain ClipDomain::rectangle(double xmin, double ymin, double xmax, double ymax)
  {
    ClipDomain d;
    d.shape = Shape::rectangle;
    d.xmin  = xmin;
    d.ymin  = ymin;
    d.xmax  = xmax;
    d.ymax  = ymax;
    return d;
  }

  ClipDomain ClipDomain::circle(double cx, double cy, double radius, int sides)
  {
    ClipDomain d;
    d.shape        = Shape::circle;
    d.cx           = cx;
    d.cy           = cy;
    d.radius       = radius;
    d.circle_sides = sides;
    return d;
  }

  void ClipDomain::validate(const std::string &where) const
  {
    const double inf = HUGE_VAL;
    if (shape == Shape::rectangle)
      {
        check_range(where, "xmin", xmin, -inf, inf, true, true);
        check_range(where, "ymin", ymin, -inf, inf, true, true);
        check_range(where, "xmax", xmax, xmin, inf, true, true);
        check_range(where, "ymax", ymax, ymin, inf, true, true);
      }
    else
      {
        check_range(where, "cx", cx, -inf, inf, true, true);
        check_range(where, "cy", cy, -inf, inf, true, true);
        check_range(where, "radius", radius, 0, inf, true, true);
        check_range(where, "circle_sides", circle_sides, 3, 1e6);
      }
  }

  void ClipDomain::polygon(std::vector<double> &x, std::vector<double> &y) const
  {
    x.clear();
    y.clear();
    if (shape == Shape::rectangle)
      {
        x = {xmin, xmax, xmax, xmin};
        y = {ymin, ymin, ymax, ymax};
        return;
      }
    for (int k = 0; k < circle_sides; ++k)
      {
        const double phi = 2 * M_PI * k / circle_sides;
        x.push_back(cx + radius * std::cos(phi));
        y.push_back(cy + radius * std::sin(phi));
      }
  }

  double ClipDomain::area() const
  {
    if (shape == Shape::rectangle)
      return (xmax - xmin) * (ymax - ymin);
    // Regular inscribed n-gon: n/2 R^2 sin(2 pi / n).
    return 0.5 * circle_sides * radius * radius * std::sin(2 * M_PI / circle_sides);
  }

  int Tessellation::shared_edge(int c, int d) const
  {
    for (int e = begin(c); e < end(c); ++e)
      if (edge_neighbour[e] == d)
        return e;
    return -1;
  }

  Tessellation laguerre_tessellation(const std::vector<double> &x,
                                     const std::vector<double> &y,
                                     const std::vector<double> &radius,
                                     const ClipDomain          &domain)
  {
    const std::string where = "laguerre_tessellation";
    if (x.size() != y.size() || x.size() != radius.size())
      throw InputError(where + ": x, y and radius must have the same length (got " +
                       std::to_string(x.size()) + ", " + std::to_string(y.size()) + ", " +
                       std::to_string(radius.size()) + ")");
    domain.validate(where + " domain");
    const int    n   = static_cast<int>(x.size());
    const double inf = HUGE_VAL;
    for (int i = 0; i < n; ++i)
      {
        const std::string w = where + " disk " + std::to_string(i);
        check_range(w, "x", x[i], -inf, inf, true, true);
        check_range(w, "y", y[i], -inf, inf, true, true);
        check_range(w, "radius", radius[i], 0, inf, false, true);
      }

    // ---- regular triangulation (CGAL) ------------------------------------
    std::vector<std::pair<WeightedP, int>> points;
    points.reserve(n);
    for (int i = 0; i < n; ++i)
      points.emplace_back(WeightedP(BareP(x[i], y[i]), radius[i] * radius[i]), i);
    Regular rt;
    rt.insert(points.begin(), points.end());

    // Visible (non-hidden) disks; any other disk, hidden by the weights or
    // a duplicate centre that CGAL kept only once, has an empty cell.
    std::vector<char> visible(n, 0);
    for (auto v = rt.finite_vertices_begin(); v != rt.finite_vertices_end(); ++v)
      visible[v->info()] = 1;

    // Neighbour lists (CSR) from the finite edges.
    std::vector<std::pair<int, int>> pairs;
    for (auto e = rt.finite_edges_begin(); e != rt.finite_edges_end(); ++e)
      {
        const int a = e->first->vertex(Regular::cw(e->second))->info();
        const int b = e->first->vertex(Regular::ccw(e->second))->info();
        pairs.emplace_back(a, b);
        pairs.emplace_back(b, a);
      }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<int> nb_offset(n + 1, 0);
    for (const auto &p : pairs)
      ++nb_offset[p.first + 1];
    for (int i = 0; i < n; ++i)
      nb_offset[i + 1] += nb_offset[i];

    // ---- clip each cell ----------------------------------------------------
    std::vector<double> dom_x, dom_y;
    domain.polygon(dom_x, dom_y);
    double diameter = 0;
    for (std::size_t a = 0; a < dom_x.size(); ++a)
      for (std::size_t b = a + 1; b < dom_x.size(); ++b)
        diameter =
            std::max(diameter, std::hypot(dom_x[a] - dom_x[b], dom_y[a] - dom_y[b]));
    const double tol = degenerate_edge_fraction * diameter;

    Tessellation t;
    t.area.assign(n, 0.0);
    t.centroid_x = x;
    t.centroid_y = y;
    t.empty_reason.assign(n, EmptyCellReason::none);
    t.offset.assign(n + 1, 0);

    LabelledPolygon poly, work;
    for (int i = 0; i < n; ++i)
      {
        t.offset[i + 1] = t.offset[i];
        if (!visible[i])
          {
            t.empty_reason[i] = EmptyCellReason::hidden;
            t.empty_cells.push_back(i);
            continue;
          }
        poly.clear();
        for (std::size_t k = 0; k < dom_x.size(); ++k)
          poly.push(dom_x[k] - x[i], dom_y[k] - y[i], Tessellation::boundary);
        const double wi = radius[i] * radius[i];
        for (int k = nb_offset[i]; k < nb_offset[i + 1] && poly.size() >= 3; ++k)
          {
            const int    j  = pairs[k].second;
            const double dx = x[j] - x[i], dy = y[j] - y[i];
            const double wj = radius[j] * radius[j];
            clip(poly, 2 * dx, 2 * dy, dx * dx + dy * dy + wi - wj, j, work);
            std::swap(poly, work);
          }
        drop_degenerate_edges(poly, tol);
        // Area and centroid, shoelace formula relative to the disk centre.
        double a2 = 0, cx6 = 0, cy6 = 0;
        for (std::size_t k = 0; k < poly.size(); ++k)
          {
            const std::size_t m   = (k + 1) % poly.size();
            const double      crs = poly.x[k] * poly.y[m] - poly.x[m] * poly.y[k];
            a2 += crs;
            cx6 += (poly.x[k] + poly.x[m]) * crs;
            cy6 += (poly.y[k] + poly.y[m]) * crs;
          }
        if (poly.size() < 3 || !(a2 > 0))
          {
            t.empty_reason[i] = EmptyCellReason::outside_domain;
            t.empty_cells.push_back(i);
            continue;
          }
        t.area[i]       = 0.5 * a2;
        t.centroid_x[i] = x[i] + cx6 / (3 * a2);
        t.centroid_y[i] = y[i] + cy6 / (3 * a2);
        for (std::size_t k = 0; k < poly.size(); ++k)
          {
            const std::size_t m = (k + 1) % poly.size();
            t.vertex_x.push_back(x[i] + poly.x[k]);
            t.vertex_y.push_back(y[i] + poly.y[k]);
            t.edge_neighbour.push_back(poly.label[k]);
            t.edge_length.push_back(
                std::hypot(poly.x[m] - poly.x[k], poly.y[m] - poly.y[k]));
          }
        t.offset[i + 1] = static_cast<int>(t.vertex_x.size());
      }
    return t;
  }
} // namespace demfem::dem::voronoi
