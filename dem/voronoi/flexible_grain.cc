// Finite-element mesh of flexible Voronoi grains (dem/voronoi/flexible_grain.h).
#include "dem/voronoi/flexible_grain.h"

#include "dem/engine/types.h"

#include <algorithm>
#include <cmath>

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

  FlexibleGrainMesh::FlexibleGrainMesh(const Tessellation &tess, const GrainElasticity &m)
      : mat(m)
  {
    m.validate("FlexibleGrainMesh");
    lambda      = m.lame_lambda();
    mu          = m.shear_modulus();
    const int n = tess.n_cells();
    grain_node_offset.assign(1, 0);
    grain_triangle_offset.assign(1, 0);
    for (int c = 0; c < n; ++c)
      {
        const int k = tess.end(c) - tess.begin(c);
        if (k >= 3)
          {
            const int first = n_nodes();
            x0.push_back(tess.centroid_x[c]);
            y0.push_back(tess.centroid_y[c]);
            for (int e = tess.begin(c); e < tess.end(c); ++e)
              {
                x0.push_back(tess.vertex_x[e]);
                y0.push_back(tess.vertex_y[e]);
              }
            node_grain.resize(x0.size(), c);
            mass.resize(x0.size(), 0.0);
            for (int j = 0; j < k; ++j)
              {
                const int a = first, b = first + 1 + j, d = first + 1 + (j + 1) % k;
                // Reference gradients of the linear shape functions:
                // grad N_a = (y_b - y_d, x_d - x_b) / (2 A), cyclic.
                const int    v[3] = {a, b, d};
                const double A2 =
                    (x0[b] - x0[a]) * (y0[d] - y0[a]) - (x0[d] - x0[a]) * (y0[b] - y0[a]);
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
              }
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

  double FlexibleGrainMesh::add_internal_forces(const double *x, const double *y,
                                                double *fx, double *fy) const
  {
    const int ne     = n_triangles();
    double    energy = 0;
    for (int e = 0; e < ne; ++e)
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
        energy += 0.5 * V * (S[0] * Exx + S[1] * Eyy + 2 * S[2] * Exy);
      }
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
