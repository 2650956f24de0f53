// Explicit dynamics: a plane-strain bar under a suddenly applied end load
// settles, with mass-proportional damping, on the static solution.
#include <catch2/catch.hpp>

#include <deal.II/grid/grid_generator.h>

#include "fem/explicit_dynamics.h"
#include "fem/mesh.h"
#include "tests/fem/kirsch.h"

#include <cmath>
#include <iostream>

using namespace demfem;

TEST_CASE("Explicit bar under a step load settles on the static solution",
          "[fem][explicit]")
{
  test::ensure_mpi();
  const double L = 2.0, H = 0.4, E = 1e9, nu = 0.25, F = 1e6; // F per unit thickness
  dealii::parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
  dealii::GridGenerator::subdivided_hyper_rectangle(tria, {20, 4}, dealii::Point<2>(0, 0),
                                                    dealii::Point<2>(L, H), true);
  // colorize: 0 = x min, 1 = x max, 2 = y min, 3 = y max. Left end: roller
  // in x (id 1); bottom: roller in y (id 5); right end: loaded interface (id 2).
  for (const auto &cell : tria.active_cell_iterators())
    for (const auto &face : cell->face_iterators())
      if (face->at_boundary())
        {
          const auto id = face->boundary_id();
          face->set_boundary_id(id == 0 ? 1 : id == 1 ? 2 : id == 2 ? 5 : 0);
        }

  fem::ExplicitSettings s;
  s.young_modulus = E;
  s.poisson_ratio = nu;
  s.density       = 2000;
  s.mass_scaling  = 1.0;
  s.fixed         = {{1, {true, false}}, {5, {false, true}}};
  // 30 % of critical damping for the fundamental axial mode, omega_1 =
  // pi c / (2 L) with the plane-strain constrained modulus; underdamped
  // modes then decay like exp(-a t / 2) (mass-proportional damping).
  const double c = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / s.density);
  s.damping      = 0.3 * 2 * M_PI * c / (2 * L);
  fem::ExplicitDynamics<2> dyn(tria, s);
  dyn.setup();

  const double dt_crit = dyn.critical_time_step();
  // The Gershgorin estimate must be below the 1D element bound h / c.
  CHECK(dt_crit < 0.1 / c * 1.0001);
  CHECK(dt_crit > 0.1 / c * 0.3);

  // Consistent nodal forces of a uniform traction F / H on the end (Q1:
  // half weight at the two corner vertices).
  // Each rank owns some of the 5 end vertices (the test also runs on 2 ranks).
  const auto &pts = dyn.interface_vertices();
  REQUIRE(dealii::Utilities::MPI::sum(pts.size(), MPI_COMM_WORLD) == 5);
  std::vector<dealii::Tensor<1, 2>> forces(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    {
      const bool corner = (pts[i][1] < 1e-12 || pts[i][1] > H - 1e-12);
      forces[i][0]      = F / 4 * (corner ? 0.5 : 1.0);
    }
  dyn.set_interface_forces(forces);

  const double dt = 0.9 * dt_crit;
  // Settling time: amplitude ~ exp(-a t / 2) < 1e-9 needs t > 2 ln(1e9)/a;
  // twice that for modes below omega_1 (lateral modes of the bar).
  const unsigned int n_steps =
      static_cast<unsigned int>(std::ceil(4 * std::log(1e9) / s.damping / dt));
  double max_u = 0;
  for (unsigned int n = 0; n < n_steps; ++n)
    {
      dyn.step(dt);
      for (const auto &u : dyn.interface_displacements())
        max_u = std::max(max_u, u[0]);
    }
  // Static plane-strain solution: uniform sigma_xx = F / H, sigma_yy = 0,
  // eps_xx = (1 - nu^2) sigma_xx / E (exact in Q1).
  const double u_static = (1 - nu * nu) * F / H * L / E;
  const auto   u_end    = dyn.interface_displacements();
  double       err      = 0;
  for (std::size_t i = 0; i < u_end.size(); ++i)
    {
      err                    = std::max(err, std::abs(u_end[i][0] - u_static) / u_static);
      const double uy_static = -nu / (1 - nu) * (1 - nu * nu) * F / H / E * pts[i][1];
      err = std::max(err, std::abs(u_end[i][1] - uy_static) / u_static);
    }
  err   = dealii::Utilities::MPI::max(err, MPI_COMM_WORLD);
  max_u = dealii::Utilities::MPI::max(max_u, MPI_COMM_WORLD);
  std::cout << "explicit bar: dt_crit " << dt_crit << " s (h/c = " << 0.1 / c << "), "
            << n_steps << " steps, overshoot " << max_u / u_static
            << ", final relative error " << err << ", kinetic energy "
            << dyn.kinetic_energy() << std::endl;
  CHECK(err < 1e-6);
  // A suddenly applied load overshoots the static value (dynamic factor
  // up to 2 undamped); damping keeps it between 1 and 2.
  CHECK(max_u > u_static);
  CHECK(max_u < 2 * u_static);
}

// The coupling interface on the committed DEM-embedding mesh: a uniform
// pressure p on the interface circle r = b (as nodal forces on the id-2
// vertices), far field r = R fixed. The damped explicit solution settles on
// the plane-strain Lame solution u(b) = B (1/b - b/R^2),
// B = p / (2 (lambda + mu) / R^2 + 2 mu / b^2). Q1 on 48 cells around: the
// measured error is 0.32 % (straight Q1 chords on the circle); limit 1 %.
TEST_CASE("Explicit ring under interface pressure settles on Lame", "[fem][explicit]")
{
  test::ensure_mpi();
  dealii::parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
  fem::read_gmsh_mesh(tria, std::string(DEMFEM_SOURCE_DIR) + "/meshes/tunnel_dem_2d.msh");
  const double          b = 3.0, R = 30.0, p = 1e6;
  fem::ExplicitSettings s;
  s.young_modulus = 1e9;
  s.poisson_ratio = 0.25;
  s.density       = 2000;
  const double E = s.young_modulus, nu = s.poisson_ratio;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double c = std::sqrt((lambda + 2 * mu) / s.density);
  // Half-critical damping of the lowest axisymmetric mode (quarter wave
  // across the ring).
  s.damping = 0.5 * 2 * M_PI * c / (2 * (R - b));
  fem::ExplicitDynamics<2> dyn(tria, s);
  dyn.setup();

  const auto        &pts = dyn.interface_vertices();
  const unsigned int n   = dealii::Utilities::MPI::sum(pts.size(), MPI_COMM_WORLD);
  REQUIRE(n == 48);
  // Equally spaced vertices: each carries the pressure on half of its two
  // chords, p 2 b sin(pi/n), directed away from the tunnel axis.
  std::vector<dealii::Tensor<1, 2>> forces(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    forces[i] = p * 2 * b * std::sin(M_PI / n) * pts[i] / pts[i].norm();
  dyn.set_interface_forces(forces);

  const double       dt = 0.9 * dyn.critical_time_step();
  const unsigned int n_steps =
      static_cast<unsigned int>(4 * std::log(1e8) / s.damping / dt);
  for (unsigned int k = 0; k < n_steps; ++k)
    dyn.step(dt);

  const double B      = p / (2 * (lambda + mu) / (R * R) + 2 * mu / (b * b));
  const double u_lame = B * (1 / b - b / (R * R));
  double       err    = 0;
  const auto   u      = dyn.interface_displacements();
  const auto   v      = dyn.interface_velocities();
  double       v_max  = 0;
  for (std::size_t i = 0; i < u.size(); ++i)
    {
      const double ur = u[i] * pts[i] / pts[i].norm();
      err             = std::max(err, std::abs(ur - u_lame) / u_lame);
      v_max           = std::max(v_max, v[i].norm());
    }
  err   = dealii::Utilities::MPI::max(err, MPI_COMM_WORLD);
  v_max = dealii::Utilities::MPI::max(v_max, MPI_COMM_WORLD);
  std::cout << "explicit ring: " << n_steps << " steps of " << dt << " s, u(b) rel error "
            << err << " vs Lame " << u_lame << " m, max interface speed " << v_max
            << std::endl;
  CHECK(err < 0.01);
  // Settled: interface speeds tiny compared with u_lame per unit time of
  // the lowest mode.
  CHECK(v_max < 1e-6 * u_lame * s.damping);
}
