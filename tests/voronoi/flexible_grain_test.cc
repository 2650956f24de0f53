// Flexible Voronoi grains (dem/voronoi/flexible_grain.h; seed 004 §2.2-2.3):
// the centroid fan of each cell, lumped masses, the patch test (a uniform
// deformation gives the same stress in every triangle, no force on the
// interior (centroid) node, and the traction-consistent forces on the
// boundary nodes), the small-strain limit against plane-strain Hooke's law,
// zero force under a large rigid motion, and the shape functions used to
// move contact velocities and forces between points and nodes.
#include "dem/engine/types.h"
#include "dem/voronoi/flexible_grain.h"
#include "dem/voronoi/tessellation.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;

namespace
{
  /// A small tessellated packing (random non-overlapping disks).
  Tessellation sample_tessellation(std::vector<double> &x, std::vector<double> &y,
                                   std::vector<double> &r)
  {
    std::mt19937                           gen(42u);
    std::uniform_real_distribution<double> u(0, 0.02), ur(1e-3, 2e-3);
    for (int k = 0; k < 2000 && x.size() < 40; ++k)
      {
        const double px = u(gen), py = u(gen), pr = ur(gen);
        bool         ok = true;
        for (std::size_t j = 0; j < x.size() && ok; ++j)
          ok = std::hypot(px - x[j], py - y[j]) > pr + r[j];
        if (ok)
          {
            x.push_back(px);
            y.push_back(py);
            r.push_back(pr);
          }
      }
    return laguerre_tessellation(x, y, r, ClipDomain::rectangle(0, 0, 0.02, 0.02));
  }

  GrainElasticity granite()
  {
    GrainElasticity m;
    m.youngs_modulus = 70e9;
    m.poisson_ratio  = 0.25;
    m.density        = 2650;
    m.thickness      = 0.01;
    return m;
  }
} // namespace

TEST_CASE("Flexible grains: centroid fan and lumped masses", "[voronoi][flexible]")
{
  std::vector<double> x, y, r;
  const auto          t = sample_tessellation(x, y, r);
  const auto          m = granite();
  FlexibleGrainMesh   mesh(t, m, FlexibleMeshOptions{0.0}); // the full fan
  REQUIRE(mesh.n_grains() == t.n_cells());
  for (int c = 0; c < t.n_cells(); ++c)
    {
      const int k = t.end(c) - t.begin(c);
      CHECK(mesh.grain_node_offset[c + 1] - mesh.grain_node_offset[c] == (k ? k + 1 : 0));
      CHECK(mesh.grain_triangle_offset[c + 1] - mesh.grain_triangle_offset[c] == k);
      double area = 0, grain_mass = 0;
      for (int e = mesh.grain_triangle_offset[c]; e < mesh.grain_triangle_offset[c + 1];
           ++e)
        {
          CHECK(mesh.triangle_area0[e] > 0);
          area += mesh.triangle_area0[e];
          // Gradients of a partition of unity sum to zero (roundoff of
          // 1/h ~ 1e3: 1e-9 absolute).
          CHECK(std::abs(mesh.dN_dX[3 * e] + mesh.dN_dX[3 * e + 1] +
                         mesh.dN_dX[3 * e + 2]) <= 1e-9);
        }
      for (int a = mesh.grain_node_offset[c]; a < mesh.grain_node_offset[c + 1]; ++a)
        grain_mass += mesh.mass[a];
      // The fan covers the cell, and the lumped masses add up to rho t A
      // (roundoff 1e-12).
      CHECK(area == Approx(t.area[c]).epsilon(1e-12));
      CHECK(grain_mass == Approx(m.density * m.thickness * t.area[c]).epsilon(1e-12));
      if (k)
        {
          // Node 0 is the centroid.
          CHECK(mesh.x0[mesh.grain_node_offset[c]] == t.centroid_x[c]);
          CHECK(mesh.y0[mesh.grain_node_offset[c]] == t.centroid_y[c]);
        }
    }
  CHECK(mesh.critical_time_step() > 0);
}

TEST_CASE("Flexible grains: patch test, uniform deformation is exact",
          "[voronoi][flexible]")
{
  // On the full centroid fan and on a mesh with merged short edges (0.2 of
  // the mean cell diameter): the CST patch test holds on any mesh.
  const double        fraction = GENERATE(0.0, 0.2);
  std::vector<double> x, y, r;
  const auto          t = sample_tessellation(x, y, r);
  const auto          m = granite();
  FlexibleGrainMesh   mesh(t, m, FlexibleMeshOptions{fraction});
  if (fraction > 0) // some vertices were merged
    REQUIRE(mesh.n_nodes() < FlexibleGrainMesh(t, m, FlexibleMeshOptions{0.0}).n_nodes());
  const double lam = m.lame_lambda(), mu = m.shear_modulus();
  const double L = 0.02;

  // x = F X with a general (non-symmetric, finite) F.
  for (const double scale : {1e-6, 0.05})
    {
      const double F[4] = {1 + 0.7 * scale, -0.4 * scale, 0.9 * scale, 1 - 0.5 * scale};
      std::vector<double> xx(mesh.n_nodes()), yy(mesh.n_nodes());
      for (int a = 0; a < mesh.n_nodes(); ++a)
        {
          xx[a] = F[0] * mesh.x0[a] + F[1] * mesh.y0[a];
          yy[a] = F[2] * mesh.x0[a] + F[3] * mesh.y0[a];
        }
      // Closed form: E = (F^T F - I)/2, S = lam tr E I + 2 mu E, P = F S.
      const double Exx    = 0.5 * (F[0] * F[0] + F[2] * F[2] - 1);
      const double Eyy    = 0.5 * (F[1] * F[1] + F[3] * F[3] - 1);
      const double Exy    = 0.5 * (F[0] * F[1] + F[2] * F[3]);
      const double Sxx    = lam * (Exx + Eyy) + 2 * mu * Exx;
      const double Syy    = lam * (Exx + Eyy) + 2 * mu * Eyy;
      const double Sxy    = 2 * mu * Exy;
      const double P[4]   = {F[0] * Sxx + F[1] * Sxy, F[0] * Sxy + F[1] * Syy,
                             F[2] * Sxx + F[3] * Sxy, F[2] * Sxy + F[3] * Syy};
      const double Pscale = std::max({std::abs(Sxx), std::abs(Syy), std::abs(Sxy)});

      // Roundoff bounds. The positions F X carry an absolute error of
      // eps X_max; a triangle with gradients G_e = max |grad N| turns it
      // into a strain error of 3 eps X_max G_e and a stress error
      // (lam + 2 mu) times that (thin triangles of the fan dominate). A node
      // force sums V_e |grad N_a| times the stress error over its triangles.
      // A factor 10 covers the few roundings of each sum.
      const double        eps = 2.3e-16, X_max = L, C = lam + 2 * mu;
      std::vector<double> stress_tol(mesh.n_triangles()), force_tol(mesh.n_nodes(), 0);
      for (int e = 0; e < mesh.n_triangles(); ++e)
        {
          double G = 0;
          for (int i = 0; i < 3; ++i)
            G = std::max(G, std::hypot(mesh.dN_dX[3 * e + i], mesh.dN_dY[3 * e + i]));
          stress_tol[e] = 10 * C * 3 * eps * X_max * G * (1 + scale) + 1e-14 * Pscale;
          for (int i = 0; i < 3; ++i)
            force_tol[mesh.triangle_nodes[3 * e + i]] +=
                mesh.triangle_area0[e] * m.thickness * G * stress_tol[e];
        }

      // Same stress in every triangle.
      for (int e = 0; e < mesh.n_triangles(); ++e)
        {
          double S[3];
          mesh.second_piola_kirchhoff(e, xx.data(), yy.data(), S);
          CHECK(std::abs(S[0] - Sxx) <= stress_tol[e]);
          CHECK(std::abs(S[1] - Syy) <= stress_tol[e]);
          CHECK(std::abs(S[2] - Sxy) <= stress_tol[e]);
        }

      std::vector<double> fx(mesh.n_nodes(), 0), fy(mesh.n_nodes(), 0);
      const double        W =
          mesh.add_internal_forces(xx.data(), yy.data(), fx.data(), fy.data());
      double total_area = 0; // of the mesh (a merged cell cuts its corners)
      for (double a : mesh.triangle_area0)
        total_area += a;
      // Strain energy t A W(E), W = S:E / 2 (relative roundoff as the
      // stresses, well inside 1e-7).
      CHECK(W == Approx(0.5 * m.thickness * total_area *
                        (Sxx * Exx + Syy * Eyy + 2 * Sxy * Exy))
                     .epsilon(1e-7));
      for (int c = 0; c < t.n_cells(); ++c)
        {
          const int n0 = mesh.grain_node_offset[c];
          if (mesh.grain_node_offset[c + 1] == n0)
            continue;
          // Interior (centroid) node: the uniform stress is in equilibrium.
          CHECK(std::abs(fx[n0]) <= force_tol[n0]);
          CHECK(std::abs(fy[n0]) <= force_tol[n0]);
          // Boundary node j (cell vertex): f = -P int N_j N dS over its two
          // cell edges = -P (L_prev N_prev + L_next N_next) / 2, N the
          // outward reference unit normals (L N = (dy, -dx) for a
          // counter-clockwise edge (dx, dy)).
          const int k = mesh.grain_node_offset[c + 1] - n0 - 1;
          for (int j = 0; j < k; ++j)
            {
              const int a = n0 + 1 + j, nxt = n0 + 1 + (j + 1) % k,
                        prv = n0 + 1 + (j + k - 1) % k;
              const double nx =
                  0.5 * ((mesh.y0[nxt] - mesh.y0[a]) + (mesh.y0[a] - mesh.y0[prv]));
              const double ny =
                  -0.5 * ((mesh.x0[nxt] - mesh.x0[a]) + (mesh.x0[a] - mesh.x0[prv]));
              const double ex = -(P[0] * nx + P[1] * ny) * m.thickness;
              const double ey = -(P[2] * nx + P[3] * ny) * m.thickness;
              CHECK(std::abs(fx[a] - ex) <= force_tol[a]);
              CHECK(std::abs(fy[a] - ey) <= force_tol[a]);
            }
        }
      // The bounds are tight enough to matter: far below the forces.
      double max_tol = 0, max_force = 0;
      for (int a = 0; a < mesh.n_nodes(); ++a)
        {
          max_tol   = std::max(max_tol, force_tol[a]);
          max_force = std::max(max_force, std::hypot(fx[a], fy[a]));
        }
      CHECK(max_tol < 1e-4 * max_force);
      if (scale == 1e-6)
        {
          // Small strain: plane-strain Hooke's law, sigma = lam tr(eps) I +
          // 2 mu eps with eps the symmetric part of F - I; Green strain and
          // Cauchy stress differ from it by O(scale) = 1e-6, hence 1e-5.
          const double exx = F[0] - 1, eyy = F[3] - 1, exy = 0.5 * (F[1] + F[2]);
          const double sxx = lam * (exx + eyy) + 2 * mu * exx;
          const double syy = lam * (exx + eyy) + 2 * mu * eyy;
          CHECK(Sxx == Approx(sxx).epsilon(1e-5));
          CHECK(Syy == Approx(syy).epsilon(1e-5));
          CHECK(Sxy == Approx(2 * mu * exy).epsilon(1e-5));
          // With E = 70 GPa, nu = 0.25: uniaxial plane strain eps_xx alone
          // gives sigma_xx = E (1 - nu) / ((1 + nu)(1 - 2 nu)) eps_xx.
          CHECK(lam + 2 * mu == Approx(70e9 * 0.75 / (1.25 * 0.5)).epsilon(1e-14));
        }
    }
}

TEST_CASE("Flexible grains: a large rigid motion gives no force", "[voronoi][flexible]")
{
  std::vector<double> x, y, r;
  const auto          t = sample_tessellation(x, y, r);
  FlexibleGrainMesh   mesh(t, granite());
  const double        phi = 1.2, cs = std::cos(phi), sn = std::sin(phi);
  std::vector<double> xx(mesh.n_nodes()), yy(mesh.n_nodes());
  for (int a = 0; a < mesh.n_nodes(); ++a)
    {
      xx[a] = cs * mesh.x0[a] - sn * mesh.y0[a] + 0.3;
      yy[a] = sn * mesh.x0[a] + cs * mesh.y0[a] - 0.1;
    }
  std::vector<double> fx(mesh.n_nodes(), 0), fy(mesh.n_nodes(), 0);
  const double W = mesh.add_internal_forces(xx.data(), yy.data(), fx.data(), fy.data());
  // Roundoff: F^T F - I ~ 1e-15, against 1e-3 strain the force scale
  // E t L 1e-3 = 1.4e4 N: 1e-9 N is far below any physical force, and a
  // small-strain element would give ~E t L (1 - cos phi) ~ 1e7 N.
  double fmax = 0;
  for (int a = 0; a < mesh.n_nodes(); ++a)
    fmax = std::max(fmax, std::hypot(fx[a], fy[a]));
  CHECK(fmax <= 1e-3);
  CHECK(std::abs(W) <= 1e-12);
}

TEST_CASE("Flexible grains: shape functions move velocities and forces consistently",
          "[voronoi][flexible]")
{
  std::vector<double> x, y, r;
  const auto          t = sample_tessellation(x, y, r);
  FlexibleGrainMesh   mesh(t, granite());
  // Deformed configuration (so the current triangles differ from the
  // reference ones).
  std::vector<double> xx(mesh.n_nodes()), yy(mesh.n_nodes());
  for (int a = 0; a < mesh.n_nodes(); ++a)
    {
      xx[a] = mesh.x0[a] + 1e-4 * std::sin(300 * mesh.y0[a]);
      yy[a] = mesh.y0[a] + 1e-4 * std::cos(200 * mesh.x0[a]);
    }
  int c = 0;
  while (mesh.grain_node_offset[c + 1] == mesh.grain_node_offset[c])
    ++c;
  // A point on the first cell edge, 30 % of the way (a contact point).
  const int    n0 = mesh.grain_node_offset[c];
  const double px = 0.7 * xx[n0 + 1] + 0.3 * xx[n0 + 2];
  const double py = 0.7 * yy[n0 + 1] + 0.3 * yy[n0 + 2];
  const int    e  = mesh.locate(c, xx.data(), yy.data(), px, py);
  REQUIRE(e == mesh.grain_triangle_offset[c]);
  double N[3];
  mesh.shape_functions(e, xx.data(), yy.data(), px, py, N);
  // On the edge: the centroid's shape function vanishes, the others are the
  // edge fractions (1e-12: roundoff of coordinates ~1e-2 over areas ~1e-6).
  CHECK(std::abs(N[0]) <= 1e-12);
  CHECK(N[1] == Approx(0.7).epsilon(1e-12));
  CHECK(N[2] == Approx(0.3).epsilon(1e-12));
  // A linear velocity field is interpolated exactly; a force returned to the
  // nodes with the same N keeps its resultant and its moment (so the
  // transfer is energy consistent: f . v(x) = sum f_m . v_m).
  const double x_c = 0.6 * xx[n0] + 0.3 * xx[n0 + 3] + 0.1 * xx[n0 + 2];
  const double y_c = 0.6 * yy[n0] + 0.3 * yy[n0 + 3] + 0.1 * yy[n0 + 2];
  const int    e2  = mesh.locate(c, xx.data(), yy.data(), x_c, y_c);
  mesh.shape_functions(e2, xx.data(), yy.data(), x_c, y_c, N);
  CHECK(std::min({N[0], N[1], N[2]}) >= 0);
  auto         v  = [](double X, double Y) { return 3.0 + 2.0 * X - 5.0 * Y; };
  double       vi = 0, Fx = 0, Fy = 0, M = 0;
  const double f[2] = {12.0, -7.0};
  for (int i = 0; i < 3; ++i)
    {
      const int a = mesh.triangle_nodes[3 * e2 + i];
      vi += N[i] * v(xx[a], yy[a]);
      Fx += N[i] * f[0];
      Fy += N[i] * f[1];
      M += xx[a] * N[i] * f[1] - yy[a] * N[i] * f[0];
    }
  CHECK(vi == Approx(v(x_c, y_c)).epsilon(1e-12));
  CHECK(Fx == Approx(f[0]).epsilon(1e-12));
  CHECK(Fy == Approx(f[1]).epsilon(1e-12));
  CHECK(M == Approx(x_c * f[1] - y_c * f[0]).epsilon(1e-10));
}
