// New contacts of the flexible Voronoi model under large displacements
// (seed 004 §2; dem/voronoi/flexible_contact_detection.cc; docs/voronoi.md,
// "New contacts"): a contact forms exactly when two disks start to overlap,
// it is frictional only, its normal force is kn A times the overlap with A
// the shorter nearest edge times the thickness, pairs are never duplicated,
// the search misses no pair, the result does not depend on the thread
// count, and a free collision conserves momentum.
#include "dem/voronoi/flexible_model.h"
#include "dem/voronoi/tessellation.h"

#include "voronoi_test_helpers.h"

#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <iostream>
#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;
using namespace demfem::dem::voronoi::testing;

namespace
{

  constexpr double R = 1e-3; // two_separate_grains' R

  /// Prescribed rigid translation: every node of grain c gets (vx, vy).
  void set_grain_velocity(FlexibleVoronoiModel &m, int c, double vx, double vy)
  {
    for (int k = m.mesh.grain_node_offset[c]; k < m.mesh.grain_node_offset[c + 1]; ++k)
      {
        m.vx[k] = vx;
        m.vy[k] = vy;
      }
  }
  /// A kinematically driven step in the central-difference order of
  /// FlexibleVoronoiModel::step: the nodes move with their (prescribed)
  /// velocities, x^n = x^(n-1) + dt v^(n-1/2), then the forces at x^n with
  /// the increments dt v^(n-1/2).
  void driven_step(FlexibleVoronoiModel &m, double dt)
  {
    for (int k = 0; k < m.mesh.n_nodes(); ++k)
      {
        m.x[k] += dt * m.vx[k];
        m.y[k] += dt * m.vy[k];
      }
    m.compute_forces(dt);
  }
  double sum(const std::vector<double> &v, int begin, int end)
  {
    double s = 0;
    for (int i = begin; i < end; ++i)
      s += v[i];
    return s;
  }
  double grain_force(const FlexibleVoronoiModel &m, int c, const std::vector<double> &f)
  {
    return sum(f, m.mesh.grain_node_offset[c], m.mesh.grain_node_offset[c + 1]);
  }
} // namespace

TEST_CASE("Flexible Voronoi new contact: forms at overlap, kn A overlap, no tension",
          "[voronoi][flexible][new_contacts]")
{
  // B starts 1.0025e-6 m beyond touching; each step closes 2e-8 m, so the
  // disks overlap first after the 51st move (not on a step boundary).
  const double         v = 0.1, dt = 1e-7;
  const auto           g  = two_separate_grains(1.8 * R + 1.0025e-6);
  const auto           cm = elastic_lattice_contacts();
  FlexibleVoronoiModel model(g.tess, g.x, g.y, g.r, grain_elasticity(50e9, 0.01), cm);
  REQUIRE(model.contacts.n_contacts() == 0);
  REQUIRE(model.n_installed_contacts == 0);
  set_grain_velocity(model, 0, v, 0);
  set_grain_velocity(model, 1, -v, 0);
  // Closed form (docs/voronoi.md, "New contacts"): the nearest edges are
  // A's right edge (2R) and B's left edge (1.6 R); A = min t = 1.6 R t and,
  // under rigid motion along the line of centres, u_n = -U from formation
  // on, so F_n = -kn A U (compression) with U = r_a + r_b - d.
  const double A     = 1.6 * R * cm.thickness;
  const double reach = 1.8 * R;
  // Roundoff: coordinates of 1e-3 m carry 2e-19 m per operation, ~1e-17 m
  // after the ~100 steps; u_n sums increments of 2e-8 m with relative
  // error 1e-16. 1e-14 m is a bound with margin against overlaps of 1e-8
  // to 1e-6 m.
  const double tol_u     = 1e-14;
  auto         overlap   = [&] { return reach - (model.disk_x(1) - model.disk_x(0)); };
  int          formed_at = -1;
  for (int s = 0; s < 100; ++s)
    {
      driven_step(model, dt);
      const double U = overlap();
      if (U <= 0)
        {
          // No contact, no contact force: only the elements' roundoff under
          // a rigid translation (1e-9 N, see flexible_model_test.cc).
          REQUIRE(model.contacts.n_contacts() == 0);
          CHECK(std::abs(grain_force(model, 1, model.fx)) <= 1e-6);
          continue;
        }
      if (formed_at < 0)
        formed_at = s;
      REQUIRE(model.contacts.n_contacts() == 1);
      double fn = 0;
      for (int p = 0; p < model.contacts.n_points(); ++p)
        {
          fn += model.contacts.fn[p];
          CHECK(model.contacts.crack[p] == PointCrack::unbonded);
        }
      CHECK(std::abs(fn + cm.kn * A * U) <= cm.kn * A * tol_u);
      // It pushes B away from A (+x) and A away from B, equal and opposite.
      CHECK(grain_force(model, 1, model.fx) ==
            Approx(cm.kn * A * U).epsilon(1e-6).margin(cm.kn * A * tol_u));
      CHECK(grain_force(model, 0, model.fx) ==
            Approx(-cm.kn * A * U).epsilon(1e-6).margin(cm.kn * A * tol_u));
    }
  CHECK(formed_at == 50); // index 50: the 51st move, the first overlap
  CHECK(model.contacts.edge_length[0] == Approx(1.6 * R).epsilon(1e-12));
  CHECK(model.contacts.point_offset[1] == 3); // Lobatto points A/6, 2A/3, A/6
  CHECK(model.contacts.area[1] == Approx(2 * A / 3).epsilon(1e-12));
  // Each point lies in (or on) its triangles, found in the current
  // configuration: no extrapolation at formation (1e-9: roundoff of
  // barycentric coordinates of points on an edge). The middle point is
  // carried by the fan triangles of the facing edges, A's right edge and
  // B's left edge (the end points sit on corners, shared with the next
  // triangle).
  for (int p = 0; p < model.contacts.n_points(); ++p)
    for (int i = 0; i < 6; ++i)
      {
        CHECK(model.point_N[6 * p + i] >= -1e-9);
        CHECK(model.point_N[6 * p + i] <= 1 + 1e-9);
      }
  double a_right = -HUGE_VAL, b_left = HUGE_VAL;
  for (int k = 0; k < model.mesh.grain_node_offset[1]; ++k)
    a_right = std::max(a_right, model.x[k]);
  for (int k = model.mesh.grain_node_offset[1]; k < model.mesh.n_nodes(); ++k)
    b_left = std::min(b_left, model.x[k]);
  for (int i : {1, 2})
    {
      CHECK(model.x[model.mesh.triangle_nodes[3 * model.triangle_a[1] + i]] == a_right);
      CHECK(model.x[model.mesh.triangle_nodes[3 * model.triangle_b[1] + i]] == b_left);
    }

  // Pull apart: unloading along the same line while they overlap, then no
  // tension at all once the disks separate; the contact stays (never a
  // second one) and bears again on re-approach.
  set_grain_velocity(model, 0, -v, 0);
  set_grain_velocity(model, 1, v, 0);
  int separated = 0;
  for (int s = 0; s < 150; ++s)
    {
      driven_step(model, dt);
      const double U = overlap();
      REQUIRE(model.contacts.n_contacts() == 1);
      double fn = 0, fs = 0;
      for (int p = 0; p < model.contacts.n_points(); ++p)
        {
          fn += model.contacts.fn[p];
          fs += std::abs(model.contacts.fs[p]);
        }
      CHECK(fs == 0);
      if (U < -tol_u)
        {
          ++separated;
          CHECK(fn == 0); // unbonded: the opening costs no force
          for (int p = 0; p < model.contacts.n_points(); ++p)
            CHECK(model.point_fx[p] == 0);
        }
      else
        CHECK(std::abs(fn + cm.kn * A * std::max(0.0, U)) <= cm.kn * A * tol_u);
    }
  CHECK(separated > 50);
  set_grain_velocity(model, 0, v, 0);
  set_grain_velocity(model, 1, -v, 0);
  for (int s = 0; s < 200; ++s)
    {
      driven_step(model, dt);
      const double U  = overlap();
      double       fn = 0;
      for (int p = 0; p < model.contacts.n_points(); ++p)
        fn += model.contacts.fn[p];
      CHECK(std::abs(fn + cm.kn * A * std::max(0.0, U)) <= cm.kn * A * tol_u);
    }
  CHECK(overlap() > 1e-7);
  CHECK(model.contacts.n_contacts() == 1);
}

TEST_CASE("Flexible Voronoi new contact: oblique approach, force along the centre line",
          "[voronoi][flexible][new_contacts]")
{
  // B approaches A along n = (cos 30, sin 30): the PCM point lies nearest
  // to A's right edge (0.13 R against 0.5 R to its top edge) and to B's
  // left edge (0.11 R against 0.4 R), so again A = 1.6 R t. The point forces
  // are along n (no shear in a rigid approach along n) with weights A/6,
  // 2A/3, A/6 at s = -L/2, 0, L/2 around the reference point on the centre
  // line: B's nodal forces have the resultant kn A U n and no moment about
  // its disk centre (the shape functions keep force and moment).
  const double         v = 0.1, dt = 1e-7, c30 = std::cos(M_PI / 6), s30 = 0.5;
  const double         d0 = 1.8 * R + 1.0025e-6;
  const auto           g  = two_separate_grains(d0 * c30, d0 * s30);
  const auto           cm = elastic_lattice_contacts();
  FlexibleVoronoiModel model(g.tess, g.x, g.y, g.r, grain_elasticity(50e9, 0.01), cm);
  REQUIRE(model.contacts.n_contacts() == 0);
  set_grain_velocity(model, 0, v * c30, v * s30);
  set_grain_velocity(model, 1, -v * c30, -v * s30);
  const double A         = 1.6 * R * cm.thickness;
  int          formed_at = -1;
  for (int s = 0; s < 100; ++s)
    {
      driven_step(model, dt);
      const double U = 1.8 * R - std::hypot(model.disk_x(1) - model.disk_x(0),
                                            model.disk_y(1) - model.disk_y(0));
      REQUIRE(model.contacts.n_contacts() == (U > 0 ? 1 : 0));
      if (U <= 0)
        continue;
      if (formed_at < 0)
        formed_at = s;
      double fn = 0, fs = 0;
      for (int p = 0; p < model.contacts.n_points(); ++p)
        {
          fn += model.contacts.fn[p];
          fs += model.contacts.fs[p];
        }
      // The overlap from the positions against u_n accumulated from the
      // velocities' projections on n: roundoff ~1e-17 m as along x, with
      // cos 30 and the hypot; 1e-14 m as in the test above.
      CHECK(std::abs(fn + cm.kn * A * U) <= cm.kn * A * 1e-14);
      CHECK(std::abs(fs) <= cm.kn * A * 1e-14);
      double Fx = 0, Fy = 0, M = 0;
      for (int k = model.mesh.grain_node_offset[1]; k < model.mesh.n_nodes(); ++k)
        {
          Fx += model.fx[k];
          Fy += model.fy[k];
          M += (model.x[k] - model.disk_x(1)) * model.fy[k] -
               (model.y[k] - model.disk_y(1)) * model.fx[k];
        }
      // 1e-6 relative + the elements' roundoff under a rigid motion
      // (1e-6 N, flexible_model_test.cc); moments of those forces over the
      // grain's 1e-3 m.
      CHECK(Fx == Approx(cm.kn * A * U * c30).epsilon(1e-6).margin(1e-6));
      CHECK(Fy == Approx(cm.kn * A * U * s30).epsilon(1e-6).margin(1e-6));
      CHECK(std::abs(M) <= 1e-6 * cm.kn * A * U * R + 1e-9);
    }
  CHECK(formed_at == 50);
  CHECK(model.contacts.edge_length[0] == Approx(1.6 * R).epsilon(1e-12));
}

TEST_CASE("Flexible Voronoi new contact: the shear force is capped by friction",
          "[voronoi][flexible][new_contacts]")
{
  const double         v = 0.1, dt = 1e-7;
  const auto           g  = two_separate_grains(1.8 * R + 1.0025e-6);
  const auto           cm = elastic_lattice_contacts();
  FlexibleVoronoiModel model(g.tess, g.x, g.y, g.r, grain_elasticity(50e9, 0.01), cm);
  set_grain_velocity(model, 0, v, 0);
  set_grain_velocity(model, 1, -v, 0);
  for (int s = 0; s < 70; ++s) // ~20 steps of approach after the first overlap
    driven_step(model, dt);
  REQUIRE(model.contacts.n_contacts() == 1);
  // B slides along +y (the contact tangent t = k x n, n = +x) at v.
  set_grain_velocity(model, 0, 0, 0);
  set_grain_velocity(model, 1, 0, v);
  const double A = 1.6 * R * cm.thickness, ks = cm.kn / cm.kratio;
  int          sliding = 0;
  for (int s = 0; s < 300; ++s)
    {
      driven_step(model, dt);
      double fn = 0, fs = 0;
      for (int p = 0; p < model.contacts.n_points(); ++p)
        {
          const double fnp = model.contacts.fn[p], fsp = model.contacts.fs[p];
          fn += fnp;
          fs += fsp;
          // Friction only (unbonded): |F_s| <= mu |F_n| per point, to the
          // roundoff of the law's product (1e-12 relative).
          CHECK(std::abs(fsp) <= cm.friction * std::abs(fnp) * (1 + 1e-12));
        }
      REQUIRE(fn < 0);
      if (s == 4)
        {
          // Elastic start: F_s = -ks A u_s, u_s = 5 v dt (the normal turns
          // by 5e-8 / 1.8e-3 rad: a relative change ~1e-9 of u_s).
          CHECK(fs == Approx(-ks * A * 5 * v * dt).epsilon(1e-6));
        }
      if (std::abs(fs) >= cm.friction * std::abs(fn) * (1 - 1e-12))
        ++sliding;
    }
  // Slip starts at u_s = mu kn U / ks = 2 mu U ~ 4e-7 m, i.e. ~40 steps.
  CHECK(sliding > 200);
  double fn = 0, fs = 0;
  for (int p = 0; p < model.contacts.n_points(); ++p)
    {
      fn += model.contacts.fn[p];
      fs += model.contacts.fs[p];
    }
  // Resisting the slide (-t on B) with the full friction mu |F_n|.
  CHECK(fs == Approx(cm.friction * fn).epsilon(1e-12));
  CHECK(model.contacts.n_contacts() == 1);
}

TEST_CASE("Flexible Voronoi new contacts: no duplicates, no pair missed",
          "[voronoi][flexible][new_contacts]")
{
  SECTION("two neighbours pushed together keep their one installed contact")
  {
    const std::vector<double> x = {0, 2 * R}, y = {0, 0}, r = {R, R};
    const auto                t =
        laguerre_tessellation(x, y, r, ClipDomain::rectangle(-R, -R, 3 * R, R));
    FlexibleVoronoiModel model(t, x, y, r, grain_elasticity(50e9, 0.01),
                               elastic_lattice_contacts());
    REQUIRE(model.contacts.n_contacts() == 1);
    set_grain_velocity(model, 0, 0.1, 0);
    set_grain_velocity(model, 1, -0.1, 0);
    for (int s = 0; s < 100; ++s)
      driven_step(model, 1e-7);
    CHECK(model.disk_x(1) - model.disk_x(0) < 2 * R - 1e-6); // overlapping
    CHECK(model.contacts.n_contacts() == 1);
    CHECK(model.verlet_candidates().empty());
  }
  SECTION("pairs overlapping at install get a stress-free contact there")
  {
    const SquareLattice  l = square_lattice();
    FlexibleVoronoiModel model(l.tess, l.x, l.y, l.r, grain_elasticity(50e9, 0.01),
                               elastic_lattice_contacts());
    int                  overlapping = 0;
    for (int a = 0; a < model.n_grains(); ++a)
      for (int b = a + 1; b < model.n_grains(); ++b)
        if (std::hypot(l.x[b] - l.x[a], l.y[b] - l.y[a]) < l.r[a] + l.r[b] &&
            l.tess.shared_edge(a, b) < 0)
          ++overlapping;
    CHECK(overlapping == 20);
    CHECK(model.contacts.n_contacts() - model.n_installed_contacts == overlapping);
    model.compute_forces(1e-8); // at rest: no contact force
    for (int p = 0; p < model.contacts.n_points(); ++p)
      CHECK(model.contacts.fn[p] == 0);
  }
  SECTION("a packing compressed by 25 %: the contacts are exactly the installed "
          "pairs and the pairs that overlapped")
  {
    // Radii 1.3 x the lattice's: the disks of neighbours overlap at
    // install, second neighbours come to overlap as the packing shrinks.
    Packing p = jittered(8, 8, 17, 0.15);
    for (double &ri : p.r)
      ri *= 1.3;
    const auto t =
        laguerre_tessellation(p.x, p.y, p.r, ClipDomain::rectangle(0, 0, p.W, p.H));
    FlexibleVoronoiModel          model(t, p.x, p.y, p.r, grain_elasticity(50e9, 0.01),
                                        elastic_lattice_contacts());
    const int                     ng = model.n_grains();
    std::set<std::pair<int, int>> expected;
    for (int k = 0; k < model.n_installed_contacts; ++k)
      expected.emplace(model.contacts.grain_a[k], model.contacts.grain_b[k]);
    REQUIRE((int)expected.size() == model.n_installed_contacts); // one per edge
    auto overlapping = [&] {
      for (int a = 0; a < ng; ++a)
        for (int b = a + 1; b < ng; ++b)
          if (t.area[a] > 0 && t.area[b] > 0 &&
              std::hypot(model.disk_x(b) - model.disk_x(a),
                         model.disk_y(b) - model.disk_y(a)) < p.r[a] + p.r[b])
            expected.emplace(a, b);
    };
    overlapping(); // pairs overlapping at install without an edge (none here)
    const int    rebuilds = model.n_verlet_rebuilds;
    const double xc = p.W / 2, yc = p.H / 2;
    for (int s = 1; s <= 250; ++s)
      {
        // Uniform shrinking about the centre, 0.1 % per step (grains are
        // strained too; only the positions matter here).
        const double f = 1 - 0.001 * s;
        for (int k = 0; k < model.mesh.n_nodes(); ++k)
          {
            model.x[k] = xc + f * (model.mesh.x0[k] - xc);
            model.y[k] = yc + f * (model.mesh.y0[k] - yc);
          }
        model.compute_forces(1e-9);
        overlapping();
      }
    std::set<std::pair<int, int>> actual;
    for (int k = 0; k < model.contacts.n_contacts(); ++k)
      actual.emplace(model.contacts.grain_a[k], model.contacts.grain_b[k]);
    CHECK((int)actual.size() == model.contacts.n_contacts()); // no duplicate
    CHECK(actual == expected);                                // none missed
    CHECK(model.contacts.n_contacts() > model.n_installed_contacts + 10);
    // The list was rebuilt (the disks moved by more than half the skin),
    // but far less often than every step.
    CHECK(model.n_verlet_rebuilds > rebuilds);
    CHECK(model.n_verlet_rebuilds < rebuilds + 50);
  }
}

TEST_CASE("Flexible Voronoi new contacts: 1 and 2 threads give bit-identical results",
          "[voronoi][flexible][new_contacts][threads]")
{
  // As the thread test of flexible_model_test.cc, on a jittered square
  // lattice (spacing h) of disks of radius 0.7 h: the diagonal pairs that
  // do not share a cell edge are 1.41 h +- the jitter apart against 1.4 h,
  // so some overlap at install (20) and others come to overlap (15 in 300
  // steps) under a converging velocity field (40 m/s at the sides) with
  // random velocities.
  const SquareLattice                    l = square_lattice();
  const double                           h = l.h;
  const auto                            &x = l.x, &y = l.y, &r = l.r;
  const auto                            &t = l.tess;
  std::uniform_real_distribution<double> u(-1, 1);
  int                                    formed_in_run = 0, formed_at_install = 0;
  auto                                   run = [&](int threads) {
    const int old = omp_get_max_threads();
    omp_set_num_threads(threads);
    FlexibleVoronoiModel model(t, x, y, r, grain_elasticity(50e9, 0.01),
                                                                 elastic_lattice_contacts());
    model.parallel_threshold = 0; // threads even on this small model
    model.damping       = 0.1;
    const int installed = model.contacts.n_contacts();
    formed_at_install = installed - model.n_installed_contacts;
    std::mt19937_64 gen(4);
    for (int k = 0; k < model.mesh.n_nodes(); ++k)
      {
        model.vx[k] = -40 * (model.x[k] - 6 * h) / (6 * h) + 1.0 * u(gen);
        model.vy[k] = -40 * (model.y[k] - 6 * h) / (6 * h) + 1.0 * u(gen);
      }
    const double dt = model.stable_time_step(0.5);
    for (int s = 0; s < 300; ++s)
      model.step(dt);
    omp_set_num_threads(old);
    formed_in_run = model.contacts.n_contacts() - installed;
    return model;
  };
  const auto one = run(1), two = run(2);
  INFO("contacts formed at install " << formed_at_install << ", in the run "
                                     << formed_in_run);
  CHECK(formed_in_run > 0);
  CHECK(one.contacts.grain_a == two.contacts.grain_a);
  CHECK(one.contacts.grain_b == two.contacts.grain_b);
  CHECK(one.x == two.x);
  CHECK(one.y == two.y);
  CHECK(one.vx == two.vx);
  CHECK(one.fx == two.fx);
  CHECK(one.fy == two.fy);
  CHECK(one.contacts.fn == two.contacts.fn);
  CHECK(one.contacts.fs == two.contacts.fs);
}

TEST_CASE("Flexible Voronoi new contact: a free collision conserves momentum",
          "[voronoi][flexible][new_contacts]")
{
  // Grain A at 1 m/s against B at rest, no damping, no applied force: the
  // contact and element forces sum to zero (sum N = 1 on each side), so the
  // total momentum sum m v is constant to roundoff.
  const auto           g  = two_separate_grains(1.8 * R + 1e-6);
  const auto           cm = elastic_lattice_contacts();
  FlexibleVoronoiModel model(g.tess, g.x, g.y, g.r, grain_elasticity(50e9, 0.01), cm);
  set_grain_velocity(model, 0, 1.0, 0);
  // The time step must cover the contact spring that is not there yet:
  // 2 sqrt(m / k) with the lightest node and the whole contact's kn A.
  double m_min = HUGE_VAL;
  for (double m : model.mesh.mass)
    m_min = std::min(m_min, m);
  const double dt =
      0.3 * std::min(model.stable_time_step(1.0),
                     2 * std::sqrt(m_min / (cm.kn * 1.6 * R * cm.thickness)));
  auto momentum = [&] {
    double px = 0, py = 0;
    for (int k = 0; k < model.mesh.n_nodes(); ++k)
      {
        px += model.mesh.mass[k] * model.vx[k];
        py += model.mesh.mass[k] * model.vy[k];
      }
    return std::make_pair(px, py);
  };
  const auto   p0      = momentum();
  const double ke0     = model.kinetic_energy();
  bool         touched = false, separated = false;
  for (int s = 0; s < 20000 && !separated; ++s)
    {
      model.step(dt);
      const bool overlap = model.disk_x(1) - model.disk_x(0) < 1.8 * R;
      touched            = touched || overlap;
      separated          = touched && !overlap;
      const auto pk      = momentum();
      // Each step adds dt sum F to sum m v, sum F a roundoff sum of forces
      // up to kn A U ~ 1e5 N; relative 1e-12 of p0 is ~1e3 such roundoffs.
      CHECK(std::abs(pk.first - p0.first) <= 1e-12 * std::abs(p0.first));
      CHECK(std::abs(pk.second) <= 1e-12 * std::abs(p0.first));
    }
  REQUIRE(touched);
  REQUIRE(separated);
  REQUIRE(model.contacts.n_contacts() == 1);
  // After the collision B moves away from A (+x) with a positive share of
  // the momentum, and no energy was created: kinetic + strain energy of
  // the grains (the contact is unloaded) within the central-difference
  // error, O((omega dt)^2), a few 1e-3 at 0.3 of the critical step
  // (measured 1.4e-4).
  double pb = 0;
  for (int k = model.mesh.grain_node_offset[1]; k < model.mesh.n_nodes(); ++k)
    pb += model.mesh.mass[k] * model.vx[k];
  CHECK(pb > 0.5 * p0.first);
  std::vector<double> fx(model.mesh.n_nodes()), fy(model.mesh.n_nodes());
  const double strain = model.mesh.add_internal_forces(model.x.data(), model.y.data(),
                                                       fx.data(), fy.data());
  const double e1     = model.kinetic_energy() + strain;
  INFO("energy after / before: " << e1 / ke0);
  CHECK(e1 == Approx(ke0).epsilon(2e-3));
}

TEST_CASE("Flexible Voronoi new contacts: measure the search's cost",
          "[.measure][voronoi][flexible][new_contacts]")
{
  // By hand (docs/voronoi.md, "New contacts"): the per-step check of the
  // Verlet list and one rebuild, per grain, on a 64 x 64 jittered lattice.
  const Packing p = jittered(64, 64, 5, 0.15);
  const auto    t =
      laguerre_tessellation(p.x, p.y, p.r, ClipDomain::rectangle(0, 0, p.W, p.H));
  FlexibleVoronoiModel model(t, p.x, p.y, p.r, grain_elasticity(50e9, 0.01),
                             elastic_lattice_contacts());
  const int            n     = 2000;
  double               start = omp_get_wtime();
  for (int s = 0; s < n; ++s)
    model.detect_new_contacts(1e-9);
  const double check     = (omp_get_wtime() - start) / (double(n) * model.n_grains());
  const int    rebuilds0 = model.n_verlet_rebuilds;
  start                  = omp_get_wtime();
  for (int s = 0; s < 20; ++s)
    {
      // Grain 0's disk jumps by 1 mm (> skin / 2): a rebuild per call.
      model.x[model.centroid_node(0)] += (s % 2 ? -1 : 1) * 1e-3;
      model.detect_new_contacts(1e-9);
    }
  const double rebuild = (omp_get_wtime() - start) / (20.0 * model.n_grains());
  std::cout << model.n_grains() << " grains, " << model.verlet_candidates().size()
            << " candidates: check " << check * 1e9 << " ns per grain-step, rebuild "
            << rebuild * 1e9 << " ns per grain (" << model.n_verlet_rebuilds - rebuilds0
            << " rebuilds)\n";
}
