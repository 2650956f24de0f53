// Finite-element mesh of flexible Voronoi grains (dem/voronoi/flexible_grain.h).
#include "dem/voronoi/flexible_grain.h"

#include "dem/engine/types.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace demfem::dem::voronoi
{
  void GrainElasticity::validate(const std::string &where) const
  {
    const double inf = HUGE_VAL;
    check_range(where, "youngs_modulus", youngs_modulus, 0, inf, true, true);
    check_range(where, "poisson_ratio", poisson_ratio, 0, 0.5, false, true);
    check_range(where, "density", density, 0, inf, true, true);
    check_range(where, "thickness", thickness, 0, inf, true, true);
  }

  void FlexibleMeshOptions::validate(const std::string &where) const
  {
    // Above 0.5 a merge could swallow an edge of an average cell.
    check_range(where, "min_edge_fraction", min_edge_fraction, 0, 0.5, false, true);
  }

  namespace
  {
    /// Twice the signed area of (a, b, d).
    double area2(double xa, double ya, double xb, double yb, double xd, double yd)
    {
      return (xb - xa) * (yd - ya) - (xd - xa) * (yb - ya);
    }

    /// The boundary nodes of one cell: consecutive runs of its vertices
    /// (cyclic), each at the mean of its vertices.
    struct Clusters
    {
      std::vector<std::vector<int>> members; ///< local vertex indices
      std::vector<double>           x, y;
      void                          place(int j, const double *vx, const double *vy)
      {
        x[j] = y[j] = 0;
        for (int v : members[j])
          {
            x[j] += vx[v];
            y[j] += vy[v];
          }
        x[j] /= members[j].size();
        y[j] /= members[j].size();
      }
    };

    /// Greedy merging of the cell's vertices (vx, vy; k of them, counter-
    /// clockwise around the centroid cx, cy): the shortest boundary edge
    /// below `tol` is merged first, the lengths re-measured after each merge;
    /// a merge that would give a fan triangle of non-positive area is
    /// skipped; at least three nodes stay.
    Clusters merge_vertices(const double *vx, const double *vy, int k, double cx,
                            double cy, double tol)
    {
      Clusters cl;
      for (int v = 0; v < k; ++v)
        {
          cl.members.push_back({v});
          cl.x.push_back(vx[v]);
          cl.y.push_back(vy[v]);
        }
      std::vector<std::pair<double, int>> order;
      while (tol > 0 && cl.x.size() > 3)
        {
          const int n = static_cast<int>(cl.x.size());
          order.clear();
          for (int j = 0; j < n; ++j)
            {
              const int    l = (j + 1) % n;
              const double d = std::hypot(cl.x[l] - cl.x[j], cl.y[l] - cl.y[j]);
              if (d < tol)
                order.emplace_back(d, j);
            }
          std::sort(order.begin(), order.end());
          bool merged = false;
          for (const auto &[d, j] : order)
            {
              const int l = (j + 1) % n, prv = (j + n - 1) % n, nxt = (l + 1) % n;
              double    mx = 0, my = 0, count = 0;
              for (int q : {j, l})
                for (int v : cl.members[q])
                  {
                    mx += vx[v];
                    my += vy[v];
                    ++count;
                  }
              mx /= count;
              my /= count;
              // The two fan triangles next to the merged node must stay
              // positive (a convex cell keeps them so unless the centroid is
              // very close to the boundary).
              if (!(area2(cx, cy, cl.x[prv], cl.y[prv], mx, my) > 0 &&
                    area2(cx, cy, mx, my, cl.x[nxt], cl.y[nxt]) > 0))
                continue;
              cl.members[j].insert(cl.members[j].end(), cl.members[l].begin(),
                                   cl.members[l].end());
              cl.place(j, vx, vy);
              cl.members.erase(cl.members.begin() + l);
              cl.x.erase(cl.x.begin() + l);
              cl.y.erase(cl.y.begin() + l);
              merged = true;
              break;
            }
          if (!merged)
            break;
        }
      return cl;
    }
  } // namespace

  FlexibleGrainMesh::FlexibleGrainMesh(const Tessellation &tess, const GrainElasticity &m,
                                       const FlexibleMeshOptions &options)
      : mat(m)
  {
    m.validate("FlexibleGrainMesh");
    options.validate("FlexibleGrainMesh");
    lambda      = m.lame_lambda();
    mu          = m.shear_modulus();
    const int n = tess.n_cells();
    // Mean equivalent diameter of the non-empty cells: one length for the
    // whole tessellation (see the header).
    double d_sum = 0;
    int    cells = 0;
    for (int c = 0; c < n; ++c)
      if (tess.end(c) - tess.begin(c) >= 3)
        {
          d_sum += 2 * std::sqrt(tess.area[c] / M_PI);
          ++cells;
        }
    merge_distance = cells ? options.min_edge_fraction * d_sum / cells : 0.0;
    vertex_node.assign(tess.vertex_x.size(), -1);
    grain_node_offset.assign(1, 0);
    grain_triangle_offset.assign(1, 0);
    for (int c = 0; c < n; ++c)
      {
        const int k = tess.end(c) - tess.begin(c);
        if (k >= 3)
          {
            const int      first = n_nodes();
            const Clusters cl    = merge_vertices(
                   &tess.vertex_x[tess.begin(c)], &tess.vertex_y[tess.begin(c)], k,
                   tess.centroid_x[c], tess.centroid_y[c], merge_distance);
            const int kc = static_cast<int>(cl.x.size());
            x0.push_back(tess.centroid_x[c]);
            y0.push_back(tess.centroid_y[c]);
            for (int j = 0; j < kc; ++j)
              {
                x0.push_back(cl.x[j]);
                y0.push_back(cl.y[j]);
                for (int v : cl.members[j])
                  vertex_node[tess.begin(c) + v] = first + 1 + j;
              }
            node_grain.resize(x0.size(), c);
            mass.resize(x0.size(), 0.0);
            double coarse_area = 0;
            for (int j = 0; j < kc; ++j)
              {
                const int a = first, b = first + 1 + j, d = first + 1 + (j + 1) % kc;
                // Reference gradients of the linear shape functions:
                // grad N_a = (y_b - y_d, x_d - x_b) / (2 A), cyclic.
                const int    v[3] = {a, b, d};
                const double A2   = area2(x0[a], y0[a], x0[b], y0[b], x0[d], y0[d]);
                if (!(A2 > 0))
                  throw InputError("FlexibleGrainMesh: cell " + std::to_string(c) +
                                   " gives a triangle of non-positive area (is its "
                                   "centroid inside it?)");
                for (int i = 0; i < 3; ++i)
                  {
                    const int p = v[(i + 1) % 3], q = v[(i + 2) % 3];
                    triangle_nodes.push_back(v[i]);
                    dN_dX.push_back((y0[p] - y0[q]) / A2);
                    dN_dY.push_back((x0[q] - x0[p]) / A2);
                    mass[v[i]] += m.density * m.thickness * A2 / 6;
                  }
                triangle_area0.push_back(A2 / 2);
                coarse_area += A2 / 2;
              }
            // The grain keeps the mass of its cell (see the header).
            const double scale = tess.area[c] / coarse_area;
            for (int a = first; a < n_nodes(); ++a)
              mass[a] *= scale;
          }
        grain_node_offset.push_back(n_nodes());
        grain_triangle_offset.push_back(n_triangles());
      }
  }

  void FlexibleGrainMesh::deformation_gradient(int e, const double *x, const double *y,
                                               double F[4]) const
  {
    F[0] = F[1] = F[2] = F[3] = 0;
    for (int i = 0; i < 3; ++i)
      {
        const int a = triangle_nodes[3 * e + i];
        F[0] += x[a] * dN_dX[3 * e + i];
        F[1] += x[a] * dN_dY[3 * e + i];
        F[2] += y[a] * dN_dX[3 * e + i];
        F[3] += y[a] * dN_dY[3 * e + i];
      }
  }

  void FlexibleGrainMesh::second_piola_kirchhoff(int e, const double *x, const double *y,
                                                 double S[3]) const
  {
    double F[4];
    deformation_gradient(e, x, y, F);
    // Green strain E = (F^T F - I) / 2.
    const double Exx = 0.5 * (F[0] * F[0] + F[2] * F[2] - 1);
    const double Eyy = 0.5 * (F[1] * F[1] + F[3] * F[3] - 1);
    const double Exy = 0.5 * (F[0] * F[1] + F[2] * F[3]);
    const double tr  = Exx + Eyy;
    S[0]             = lambda * tr + 2 * mu * Exx;
    S[1]             = lambda * tr + 2 * mu * Eyy;
    S[2]             = 2 * mu * Exy;
  }

  void FlexibleGrainMesh::cauchy_stress(int e, const double *x, const double *y,
                                        double sigma[4]) const
  {
    double F[4], S[3];
    deformation_gradient(e, x, y, F);
    second_piola_kirchhoff(e, x, y, S);
    const double J = F[0] * F[3] - F[1] * F[2];
    // F S = {FS_xX, FS_xY; FS_yX, FS_yY}, then (F S) F^T / J.
    const double a = F[0] * S[0] + F[1] * S[2], b = F[0] * S[2] + F[1] * S[1];
    const double c = F[2] * S[0] + F[3] * S[2], d = F[2] * S[2] + F[3] * S[1];
    sigma[0] = (a * F[0] + b * F[1]) / J;
    sigma[1] = (c * F[2] + d * F[3]) / J;
    sigma[2] = (a * F[2] + b * F[3]) / J;
    // S_zz = lambda tr(E) (E_zz = 0), sigma_zz = S_zz / J (F_zz = 1).
    const double Exx = 0.5 * (F[0] * F[0] + F[2] * F[2] - 1);
    const double Eyy = 0.5 * (F[1] * F[1] + F[3] * F[3] - 1);
    sigma[3]         = lambda * (Exx + Eyy) / J;
  }

  double FlexibleGrainMesh::triangle_forces(int e, const double *x, const double *y,
                                            double *fx, double *fy) const
  {
    double F[4], S[3];
    deformation_gradient(e, x, y, F);
    second_piola_kirchhoff(e, x, y, S);
    // First Piola-Kirchhoff P = F S.
    const double Pxx = F[0] * S[0] + F[1] * S[2], PxY = F[0] * S[2] + F[1] * S[1];
    const double Pyx = F[2] * S[0] + F[3] * S[2], PyY = F[2] * S[2] + F[3] * S[1];
    const double V = triangle_area0[e] * mat.thickness;
    for (int i = 0; i < 3; ++i)
      {
        const int    a  = triangle_nodes[3 * e + i];
        const double gx = dN_dX[3 * e + i], gy = dN_dY[3 * e + i];
        fx[a] -= V * (Pxx * gx + PxY * gy);
        fy[a] -= V * (Pyx * gx + PyY * gy);
      }
    // W = lambda/2 tr(E)^2 + mu E:E, with E:E from S: W = S:E / 2.
    const double Exx = 0.5 * (F[0] * F[0] + F[2] * F[2] - 1);
    const double Eyy = 0.5 * (F[1] * F[1] + F[3] * F[3] - 1);
    const double Exy = 0.5 * (F[0] * F[1] + F[2] * F[3]);
    return 0.5 * V * (S[0] * Exx + S[1] * Eyy + 2 * S[2] * Exy);
  }

  double FlexibleGrainMesh::add_grain_internal_forces(int c, const double *x,
                                                      const double *y, double *fx,
                                                      double *fy) const
  {
    double energy = 0;
    for (int e = grain_triangle_offset[c]; e < grain_triangle_offset[c + 1]; ++e)
      energy += triangle_forces(e, x, y, fx, fy);
    return energy;
  }

  double FlexibleGrainMesh::add_internal_forces(const double *x, const double *y,
                                                double *fx, double *fy) const
  {
    double energy = 0;
    for (int e = 0; e < n_triangles(); ++e)
      energy += triangle_forces(e, x, y, fx, fy);
    return energy;
  }

  void FlexibleGrainMesh::shape_functions(int e, const double *x, const double *y,
                                          double px, double py, double N[3]) const
  {
    const int a = triangle_nodes[3 * e], b = triangle_nodes[3 * e + 1],
              d = triangle_nodes[3 * e + 2];
    // N_m = (signed area of the sub-triangle opposite node m) / (area).
    auto area2 = [](double x1, double y1, double x2, double y2, double x3, double y3) {
      return (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1);
    };
    const double A2 = area2(x[a], y[a], x[b], y[b], x[d], y[d]);
    N[0]            = area2(px, py, x[b], y[b], x[d], y[d]) / A2;
    N[1]            = area2(x[a], y[a], px, py, x[d], y[d]) / A2;
    N[2]            = 1 - N[0] - N[1];
  }

  int FlexibleGrainMesh::locate(int c, const double *x, const double *y, double px,
                                double py) const
  {
    int    best     = -1;
    double best_min = -HUGE_VAL;
    for (int e = grain_triangle_offset[c]; e < grain_triangle_offset[c + 1]; ++e)
      {
        double N[3];
        shape_functions(e, x, y, px, py, N);
        const double m = std::min({N[0], N[1], N[2]});
        if (m > best_min)
          {
            best_min = m;
            best     = e;
          }
      }
    return best;
  }

  PointStencil FlexibleGrainMesh::stencil(int c, double X, double Y) const
  {
    PointStencil s;
    const int    e = locate(c, x0.data(), y0.data(), X, Y);
    shape_functions(e, x0.data(), y0.data(), X, Y, s.w);
    for (int i = 0; i < 3; ++i)
      s.node[i] = triangle_nodes[3 * e + i];
    return s;
  }

  double FlexibleGrainMesh::critical_time_step() const
  {
    const double cp = std::sqrt((lambda + 2 * mu) / mat.density);
    double       dt = HUGE_VAL;
    for (int e = 0; e < n_triangles(); ++e)
      for (int i = 0; i < 3; ++i)
        {
          // Height onto the side opposite node i: 1 / |grad N_i|.
          const double g = std::hypot(dN_dX[3 * e + i], dN_dY[3 * e + i]);
          dt             = std::min(dt, 1 / (g * cp));
        }
    return dt;
  }
} // namespace demfem::dem::voronoi
