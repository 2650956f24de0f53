// Verification of the elastic continuum against the Kirsch solution, the 3D
// slab against plane strain, and the uniform-stress patch test.
#include <catch2/catch.hpp>

#include "fem/elastic_problem.h"
#include "tests/fem/kirsch.h"

#include <cmath>
#include <iostream>

using namespace demfem;
using dealii::Point;
using dealii::Tensor;

namespace
{
  fem::ElasticSettings base_settings(double sxx, double syy)
  {
    fem::ElasticSettings s;
    s.sxx          = sxx;
    s.syy          = syy;
    s.szz          = 0.5 * (sxx + syy);
    s.write_output = false;
    s.verbose      = false;
    return s;
  }

  struct WallErrors
  {
    double max_rel_u = 0, max_rel_hoop = 0;
  };

  WallErrors wall_errors(const std::vector<fem::WallVertex> &wall, const test::Kirsch &k)
  {
    WallErrors e;
    for (const auto &w : wall)
      {
        const auto   ue = k.displacement(w.x[0], w.x[1]);
        const double du = std::hypot(w.u[0] - ue[0], w.u[1] - ue[1]);
        e.max_rel_u     = std::max(e.max_rel_u, du / ue.norm());
        const double th = std::atan2(w.x[1], w.x[0]);
        const double r  = std::hypot(w.x[0], w.x[1]);
        const double tx = -w.x[1] / r, ty = w.x[0] / r;
        const double hoop = tx * tx * w.stress[0][0] + ty * ty * w.stress[1][1] +
                            2 * tx * ty * w.stress[0][1];
        const double he = k.wall_hoop_stress(th);
        e.max_rel_hoop  = std::max(e.max_rel_hoop, std::abs(hoop - he) / std::abs(he));
      }
    return e;
  }

  dealii::SymmetricTensor<2, 2> in_situ_2d(double sxx, double syy)
  {
    dealii::SymmetricTensor<2, 2> t;
    t[0][0] = sxx;
    t[1][1] = syy;
    return t;
  }

  // Far-field traction change of the infinite medium: (sigma_K - sigma0).n.
  void use_exact_far_field(fem::ElasticProblem<2> &problem, const test::Kirsch &k)
  {
    const auto sigma0 = in_situ_2d(k.S1, k.S2);
    problem.set_far_field_traction([k, sigma0](const Point<2> &p, const Tensor<1, 2> &n) {
      return Tensor<1, 2>((k.stress(p[0], p[1]) - sigma0) * n);
    });
  }

  WallErrors kirsch_run(fem::ElasticSettings s, bool exact_far_field, const char *label)
  {
    const test::Kirsch     k{s.radius, s.sxx, s.syy, s.young_modulus, s.poisson_ratio};
    fem::ElasticProblem<2> problem(s, MPI_COMM_WORLD);
    if (exact_far_field)
      use_exact_far_field(problem, k);
    problem.run(); // write_output = false: no files
    const auto wall = problem.wall_results();
    const auto e    = wall_errors(wall, k);
    std::cout << "Kirsch " << label << " K=" << s.syy / s.sxx
              << ": R = " << s.outer_radius << ", " << problem.n_cells() << " cells, "
              << problem.n_dofs() << " dofs, " << wall.size()
              << " wall vertices, max rel error u " << e.max_rel_u << ", hoop "
              << e.max_rel_hoop << ", CG iterations " << problem.solver_iterations()
              << std::endl;
    CHECK(wall.size() == s.cells_around << s.refinements);
    return e;
  }
} // namespace

// Default mesh of `demfem fem` (generated, outer radius 30a, 32 cells around
// the wall, degree 2) with the exact Kirsch tractions on the outer boundary,
// which removes the truncation error of the finite domain, so the 0.5 % / 2 %
// limits (docs/architecture.md, "Verification cases") test the
// discretization and the stress recovery.
// Measured (pointwise relative, max over the 32 wall vertices):
//   hydrostatic: u 0.0064 %, hoop 0.50 %;  K = 0.5: u 0.041 %, hoop 1.06 %.
// (The hoop error is that of averaging the cell stresses at the vertices.)
TEST_CASE("Kirsch plane strain on the default mesh (degree 2)", "[fem][kirsch]")
{
  test::ensure_mpi();
  for (const auto &[sxx, syy] : {std::pair{-45e6, -45e6}, std::pair{-30e6, -60e6}})
    {
      const auto e =
          kirsch_run(base_settings(sxx, syy), true, "default mesh, exact far field");
      CHECK(e.max_rel_u < 0.005);
      CHECK(e.max_rel_hoop < 0.02);
    }
}

// The physical far-field condition (far-field traction unchanged) on a
// finite domain has a truncation error ~ (a/R)^2: measured at R = 30a it is
// 0.16 % (hydrostatic) and 0.76 % (K = 0.5) of the wall displacement, so the
// 0.5 % limit needs R = 60a. Measured at R = 60a: hydrostatic u 0.035 %,
// hoop 0.50 %; K = 0.5: u 0.17 %, hoop 1.18 %.
TEST_CASE("Kirsch plane strain with the physical far field at R = 60a", "[fem][kirsch]")
{
  test::ensure_mpi();
  for (const auto &[sxx, syy] : {std::pair{-45e6, -45e6}, std::pair{-30e6, -60e6}})
    {
      auto s         = base_settings(sxx, syy);
      s.outer_radius = 60;
      const auto e   = kirsch_run(s, false, "physical far field");
      CHECK(e.max_rel_u < 0.005);
      CHECK(e.max_rel_hoop < 0.02);
    }
}

// With the exact Kirsch tractions on the outer boundary the only error left
// is the discretization error, so the L2 error of the induced displacement
// must converge at the optimal rate p + 1 (MappingQ(p) on the exact circles).
// Measured (outer radius 8a, 16 cells around, refinements 0..3), relative
// L2 errors and rates:
//   degree 1: 1.17e-1, 3.49e-2, 9.23e-3, 2.35e-3 -> rates 1.75, 1.92, 1.98
//   degree 2: 5.86e-3, 6.49e-4, 7.17e-5, 8.50e-6 -> rates 3.17, 3.18, 3.08
TEST_CASE("Kirsch L2 error converges at rate p+1", "[fem][kirsch][convergence]")
{
  test::ensure_mpi();
  const double sxx = -30e6, syy = -60e6;
  for (const unsigned int degree : {1u, 2u})
    {
      std::vector<double> errors;
      for (unsigned int ref = 0; ref < 4; ++ref)
        {
          auto s         = base_settings(sxx, syy);
          s.outer_radius = 8.0;
          s.cells_around = 16;
          s.degree       = degree;
          s.refinements  = ref;
          const test::Kirsch     k{s.radius, sxx, syy, s.young_modulus, s.poisson_ratio};
          fem::ElasticProblem<2> problem(s, MPI_COMM_WORLD);
          use_exact_far_field(problem, k);
          problem.run();
          const test::KirschDisplacement<2> exact(k);
          errors.push_back(problem.l2_error(exact) / problem.l2_norm(exact));
          std::cout << "Kirsch convergence degree " << degree << " refinement " << ref
                    << ": cells " << problem.n_cells() << ", dofs " << problem.n_dofs()
                    << ", relative L2 error " << errors.back();
          if (ref > 0)
            std::cout << ", rate " << std::log2(errors[ref - 1] / errors[ref]);
          std::cout << std::endl;
        }
      // The first step is pre-asymptotic for degree 1 (rate 1.75); the last
      // two must be within 0.2 of p + 1.
      for (unsigned int ref = 2; ref < errors.size(); ++ref)
        CHECK(std::log2(errors[ref - 1] / errors[ref]) > degree + 1 - 0.2);
    }
}

// The 3D slab (one element layer, u_z = 0 on both faces) has the 2D
// plane-strain Galerkin solution in its space (Q_p in x, y times constants
// in z), so both must agree to solver round-off; direct solvers in both.
TEST_CASE("3D slab with u_z = 0 reproduces plane strain", "[fem][slab]")
{
  test::ensure_mpi();
  auto s           = base_settings(-30e6, -60e6);
  s.sxy            = -5e6;
  s.cells_around   = 16;
  s.outer_radius   = 10.0;
  s.solver         = "direct";
  s.slab_thickness = 0.5;
  fem::ElasticProblem<2> p2(s, MPI_COMM_WORLD);
  p2.run();
  s.dimension = 3;
  fem::ElasticProblem<3> p3(s, MPI_COMM_WORLD);
  p3.run();
  const auto w2 = p2.wall_results();
  const auto w3 = p3.wall_results();
  REQUIRE(w3.size() == 2 * w2.size());
  double umax = 0, smax = 0, du = 0, ds = 0;
  for (std::size_t i = 0; i < w3.size(); ++i)
    {
      const auto &a = w2[i / 2], &b = w3[i];
      REQUIRE(std::hypot(a.x[0] - b.x[0], a.x[1] - b.x[1]) < 1e-12);
      umax = std::max(umax, a.u.norm());
      smax = std::max(smax, a.stress.norm());
      du   = std::max(du, (a.u - b.u).norm());
      ds   = std::max(ds, (a.stress - b.stress).norm());
    }
  std::cout << "slab vs plane strain: max rel difference u " << du / umax << ", stress "
            << ds / smax << std::endl;
  CHECK(du / umax < 1e-8);
  CHECK(ds / smax < 1e-8);
}

// A uniform in-situ stress applied as tractions sigma0.n on all boundaries
// (before excavation) is reproduced exactly: linear displacement fields are
// in the isoparametric space and Gauss quadrature of order p + 1 integrates
// the cofactor-weighted integrands exactly, so only round-off remains.
TEST_CASE("Uniform stress patch test is exact", "[fem][patch]")
{
  test::ensure_mpi();
  auto s         = base_settings(-30e6, -60e6);
  s.szz          = -45e6;
  s.sxy          = 12e6;
  s.sxz          = -7e6;
  s.syz          = 4e6;
  s.cells_around = 16;
  s.outer_radius = 10.0;
  s.solver       = "direct";
  for (const unsigned int degree : {1u, 2u})
    {
      s.degree = degree;
      fem::ElasticProblem<2> p2(s, MPI_COMM_WORLD);
      p2.make_grid();
      p2.setup_system();
      p2.assemble_system();
      const double e2 = p2.in_situ_patch_error();
      // 3D without rollers: all six components are loaded and checked.
      auto s3              = s;
      s3.dimension         = 3;
      s3.plane_strain_slab = false;
      s3.cells_around      = 8;
      s3.outer_radius      = 4.0;
      s3.slab_layers       = 2;
      fem::ElasticProblem<3> p3(s3, MPI_COMM_WORLD);
      p3.make_grid();
      p3.setup_system();
      p3.assemble_system();
      const double e3 = p3.in_situ_patch_error();
      std::cout << "patch test degree " << degree << ": 2D " << e2 << ", 3D " << e3
                << std::endl;
      CHECK(e2 < 1e-9);
      CHECK(e3 < 1e-9);
    }
}
