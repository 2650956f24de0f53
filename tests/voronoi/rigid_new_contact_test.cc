// New contacts of the rigid Voronoi model (seed 004 §2;
// dem/voronoi/rigid_contact_detection.cc, the search of
// dem/voronoi/new_contact_search.h shared with the flexible model;
// docs/voronoi.md, "New contacts"): a contact forms exactly when two disks
// start to overlap, it is frictional only, its normal force is kn A times
// the overlap with A the shorter nearest cell edge times the thickness,
// pairs are never duplicated, the search misses no pair, the result does
// not depend on the thread count, and a free collision conserves momentum.
#include "dem/voronoi/rigid_model.h"
#include "dem/voronoi/stable_time_step.h"
#include "dem/voronoi/tessellation.h"

#include "voronoi_test_helpers.h"

#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;
using namespace demfem::dem::voronoi::testing;

namespace
{
  ContactMaterial contact_material(double kn = 1e13)
  {
    ContactMaterial m;
    m.kn               = kn;
    m.kratio           = 2;
    m.tensile_strength = 1e12; // the installed contacts stay elastic
    m.cohesion         = 1e12;
    m.friction         = 0.5;
    m.thickness        = 0.01;
    return m.brittle();
  }

  constexpr double R = 1e-3; // two_separate_grains' R

  /// A kinematically driven step in the order of RigidVoronoiModel::step:
  /// the grains move with their (prescribed) velocities, x^n = x^(n-1) +
  /// dt v^(n-1/2), then the forces at x^n with the increments dt v^(n-1/2).
  void driven_step(RigidVoronoiModel &m, double dt)
  {
    for (int i = 0; i < m.n_grains(); ++i)
      {
        m.x[i] += dt * m.vx[i];
        m.y[i] += dt * m.vy[i];
        m.theta[i] += dt * m.omega[i];
      }
    m.compute_forces(dt);
  }
  double sum_fn(const RigidVoronoiModel &m)
  {
    double fn = 0;
    for (int p = 0; p < m.contacts.n_points(); ++p)
      fn += m.contacts.fn[p];
    return fn;
  }
} // namespace

TEST_CASE("Rigid Voronoi new contact: forms at overlap, kn A overlap, no tension",
          "[voronoi][rigid_model][new_contacts]")
{
  // B starts 1.0025e-6 m beyond touching; each step closes 2e-8 m, so the
  // disks overlap first after the 51st move (not on a step boundary).
  const double      v = 0.1, dt = 1e-7;
  const auto        g  = two_separate_grains(1.8 * R + 1.0025e-6);
  const auto        cm = contact_material();
  RigidVoronoiModel model(g.tess, g.x, g.y, g.r, 2650, cm);
  REQUIRE(model.contacts.n_contacts() == 0);
  REQUIRE(model.n_installed_contacts == 0);
  model.vx = {v, -v};
  // Closed form (docs/voronoi.md, "New contacts"): the nearest edges are
  // A's right edge (2R) and B's left edge (1.6 R); A = min t = 1.6 R t and,
  // along the line of centres, u_n = -U from formation on, so F_n = -kn A U
  // (compression) with U = r_a + r_b - d.
  const double A     = 1.6 * R * cm.thickness;
  const double reach = 1.8 * R;
  // Roundoff: coordinates of 1e-3 m carry 2e-19 m per operation, ~1e-17 m
  // after the ~100 steps; u_n sums increments of 2e-8 m with relative
  // error 1e-16. 1e-14 m is a bound with margin against overlaps of 1e-8
  // to 1e-6 m.
  const double tol_u     = 1e-14;
  auto         overlap   = [&] { return reach - (model.x[1] - model.x[0]); };
  int          formed_at = -1;
  for (int s = 0; s < 100; ++s)
    {
      driven_step(model, dt);
      const double U = overlap();
      if (U <= 0)
        {
          // No contact, no force at all (nothing else acts on the grains).
          REQUIRE(model.contacts.n_contacts() == 0);
          CHECK(model.fx[1] == 0);
          continue;
        }
      if (formed_at < 0)
        formed_at = s;
      REQUIRE(model.contacts.n_contacts() == 1);
      for (int p = 0; p < model.contacts.n_points(); ++p)
        CHECK(model.contacts.crack[p] == PointCrack::unbonded);
      CHECK(std::abs(sum_fn(model) + cm.kn * A * U) <= cm.kn * A * tol_u);
      // It pushes B away from A (+x) and A away from B, equal and opposite,
      // with no moment (points symmetric about the line of centres; the
      // moments are sums of arms ~1e-3 m times forces: roundoff 1e-16
      // relative of kn A U R).
      CHECK(std::abs(model.fx[1] - cm.kn * A * U) <= cm.kn * A * tol_u);
      CHECK(model.fx[0] == -model.fx[1]);
      CHECK(std::abs(model.mz[0]) <= 1e-12 * cm.kn * A * U * R);
      CHECK(std::abs(model.mz[1]) <= 1e-12 * cm.kn * A * U * R);
    }
  CHECK(formed_at == 50); // index 50: the 51st move, the first overlap
  CHECK(model.contacts.edge_length[0] == Approx(1.6 * R).epsilon(1e-12));
  CHECK(model.contacts.offset[0] == 0);
  CHECK(model.contacts.point_offset[1] == 3); // Lobatto points A/6, 2A/3, A/6
  CHECK(model.contacts.area[1] == Approx(2 * A / 3).epsilon(1e-12));
  CHECK(model.contacts.s[0] == Approx(-0.8 * R).epsilon(1e-9));
  CHECK(model.contacts.s[2] == Approx(0.8 * R).epsilon(1e-9));

  // Pull apart: unloading along the same line while they overlap, then no
  // tension at all once the disks separate; the contact stays (never a
  // second one) and bears again on re-approach.
  model.vx      = {-v, v};
  int separated = 0;
  for (int s = 0; s < 150; ++s)
    {
      driven_step(model, dt);
      const double U = overlap();
      REQUIRE(model.contacts.n_contacts() == 1);
      for (int p = 0; p < model.contacts.n_points(); ++p)
        CHECK(model.contacts.fs[p] == 0);
      if (U < -tol_u)
        {
          ++separated;
          CHECK(sum_fn(model) == 0); // unbonded: the opening costs no force
          CHECK(model.fx[1] == 0);
        }
      else
        CHECK(std::abs(sum_fn(model) + cm.kn * A * std::max(0.0, U)) <=
              cm.kn * A * tol_u);
    }
  CHECK(separated > 50);
  model.vx = {v, -v};
  for (int s = 0; s < 200; ++s)
    {
      driven_step(model, dt);
      const double U = overlap();
      CHECK(std::abs(sum_fn(model) + cm.kn * A * std::max(0.0, U)) <= cm.kn * A * tol_u);
    }
  CHECK(overlap() > 1e-7);
  CHECK(model.contacts.n_contacts() == 1);
}

TEST_CASE("Rigid Voronoi new contact: the nearest edge of the turned cell",
          "[voronoi][rigid_model][new_contacts]")
{
  // Grain B (disk 0.8 R) has a rectangular cell, 1.6 R wide along x and
  // 1.0 R high. Unturned, its edge nearest to the contact point is its left
  // edge (1.0 R); turned by 90 degrees before the approach, the left face
  // of the current polygon is a former horizontal edge (1.6 R). A's nearest
  // edge is its right edge (2R), so the contact length min(2R, L_B) tells
  // which polygon the selection used (seed 004 §2: "the Voronoi edge
  // closest to the contact location", in the current configuration).
  const double xb = 1.8 * R + 1.0025e-6, rb = 0.8 * R;
  const auto   ta =
      laguerre_tessellation({0.0}, {0.0}, {R}, ClipDomain::rectangle(-R, -R, R, R));
  const auto tb = laguerre_tessellation(
      {xb}, {0.0}, {rb}, ClipDomain::rectangle(xb - rb, -0.5 * R, xb + rb, 0.5 * R));
  const auto tess = concatenate(ta, tb);
  const auto cm   = contact_material();
  for (const double turn : {0.0, M_PI / 2})
    {
      RigidVoronoiModel model(tess, {0.0, xb}, {0.0, 0.0}, {R, rb}, 2650, cm);
      REQUIRE(model.contacts.n_contacts() == 0);
      model.theta[1] = turn;
      model.vx       = {0.1, -0.1};
      for (int s = 0; s < 60; ++s)
        driven_step(model, 1e-7);
      REQUIRE(model.contacts.n_contacts() == 1);
      const double L = turn == 0 ? 1.0 * R : 1.6 * R;
      CHECK(model.contacts.edge_length[0] == Approx(L).epsilon(1e-12));
      // Force kn A U along the line of centres (tolerance as above).
      const double U = 1.8 * R - (model.x[1] - model.x[0]);
      const double A = L * cm.thickness;
      CHECK(std::abs(sum_fn(model) + cm.kn * A * U) <= cm.kn * A * 1e-14);
    }
}

TEST_CASE("Rigid Voronoi new contact: the shear force is capped by friction",
          "[voronoi][rigid_model][new_contacts]")
{
  const double      v = 0.1, dt = 1e-7;
  const auto        g  = two_separate_grains(1.8 * R + 1.0025e-6);
  const auto        cm = contact_material();
  RigidVoronoiModel model(g.tess, g.x, g.y, g.r, 2650, cm);
  model.vx = {v, -v};
  for (int s = 0; s < 70; ++s) // ~20 steps of approach after the first overlap
    driven_step(model, dt);
  REQUIRE(model.contacts.n_contacts() == 1);
  // B slides along +y (the contact tangent t = k x n, n = +x) at v.
  model.vx       = {0, 0};
  model.vy       = {0, v};
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
      if (s == 4) // elastic start: F_s = -ks A u_s, u_s = 5 v dt (normal turned
                  // by 5e-8 / 1.8e-3 rad: a relative change ~1e-9 of u_s)
        CHECK(fs == Approx(-ks * A * 5 * v * dt).epsilon(1e-6));
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
  CHECK(fs == Approx(cm.friction * fn).epsilon(1e-12)); // resisting, full mu |F_n|
  CHECK(model.contacts.n_contacts() == 1);
}

TEST_CASE("Rigid Voronoi new contacts: no duplicates, no pair missed",
          "[voronoi][rigid_model][new_contacts]")
{
  SECTION("two neighbours pushed together keep their one installed contact")
  {
    const std::vector<double> x = {0, 2 * R}, y = {0, 0}, r = {R, R};
    const auto                t =
        laguerre_tessellation(x, y, r, ClipDomain::rectangle(-R, -R, 3 * R, R));
    RigidVoronoiModel model(t, x, y, r, 2650, contact_material());
    REQUIRE(model.contacts.n_contacts() == 1);
    model.vx = {0.1, -0.1};
    for (int s = 0; s < 100; ++s)
      driven_step(model, 1e-7);
    CHECK(model.x[1] - model.x[0] < 2 * R - 1e-6); // overlapping
    CHECK(model.contacts.n_contacts() == 1);
    CHECK(model.verlet_candidates().empty());
  }
  SECTION("pairs overlapping at install get a stress-free contact there")
  {
    const SquareLattice l = square_lattice();
    RigidVoronoiModel   model(l.tess, l.x, l.y, l.r, 2650, contact_material());
    int                 overlapping = 0;
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
  SECTION("a packing shrunk by 25 %: the contacts are exactly the installed "
          "pairs and the pairs that overlapped")
  {
    // Radii 1.3 x the lattice's: the disks of neighbours overlap at
    // install, second neighbours come to overlap as the packing shrinks;
    // the grains also turn, which the search does not see (disk centres).
    Packing p = jittered(8, 8, 17, 0.15);
    for (double &ri : p.r)
      ri *= 1.3;
    const auto t =
        laguerre_tessellation(p.x, p.y, p.r, ClipDomain::rectangle(0, 0, p.W, p.H));
    RigidVoronoiModel             model(t, p.x, p.y, p.r, 2650, contact_material());
    const int                     ng = model.n_grains();
    std::set<std::pair<int, int>> expected;
    for (int k = 0; k < model.n_installed_contacts; ++k)
      expected.emplace(model.contacts.grain_a[k], model.contacts.grain_b[k]);
    REQUIRE((int)expected.size() == model.n_installed_contacts); // one per edge
    auto overlapping = [&] {
      for (int a = 0; a < ng; ++a)
        for (int b = a + 1; b < ng; ++b)
          if (!model.held[a] && !model.held[b] &&
              std::hypot(model.x[b] - model.x[a], model.y[b] - model.y[a]) <
                  p.r[a] + p.r[b])
            expected.emplace(a, b);
    };
    overlapping(); // pairs overlapping at install without an edge
    const int    rebuilds = model.n_verlet_rebuilds;
    const double xc = p.W / 2, yc = p.H / 2;
    for (int s = 1; s <= 250; ++s)
      {
        const double f = 1 - 0.001 * s; // 0.1 % per step about the centre
        for (int i = 0; i < ng; ++i)
          {
            model.x[i]     = xc + f * (model.x0[i] - xc);
            model.y[i]     = yc + f * (model.y0[i] - yc);
            model.theta[i] = 0.002 * s * (i % 3 - 1);
          }
        model.compute_forces(1e-9);
        overlapping();
      }
    std::set<std::pair<int, int>> actual;
    for (int k = 0; k < model.contacts.n_contacts(); ++k)
      actual.emplace(model.contacts.grain_a[k], model.contacts.grain_b[k]);
    INFO("installed " << model.n_installed_contacts << ", formed "
                      << model.contacts.n_contacts() - model.n_installed_contacts
                      << ", rebuilds " << model.n_verlet_rebuilds - rebuilds);
    CHECK((int)actual.size() == model.contacts.n_contacts()); // no duplicate
    CHECK(actual == expected);                                // none missed
    CHECK(model.contacts.n_contacts() > model.n_installed_contacts + 10);
    // Rebuilt (the disks moved by more than half the skin), but far less
    // often than every step.
    CHECK(model.n_verlet_rebuilds > rebuilds);
    CHECK(model.n_verlet_rebuilds < rebuilds + 50);
    // Every new contact's length is one of its grains' cell edge lengths.
    for (int k = model.n_installed_contacts; k < model.contacts.n_contacts(); ++k)
      {
        CHECK(model.contacts.edge_length[k] > 0);
        CHECK(model.contacts.offset[k] == 0);
      }
  }
}

TEST_CASE("Rigid Voronoi new contacts: 1 and 2 threads give bit-identical results",
          "[voronoi][rigid_model][new_contacts][threads]")
{
  // The jittered square lattice (spacing h, disks 0.7 h): some diagonal
  // pairs overlap at install (20), others come to overlap under a
  // converging velocity field (40 m/s at the sides) with random velocities
  // and spins. Contacts softer than elsewhere (kn = 1e11 Pa/m): the grains
  // then travel a few % of h against the installed contacts before they
  // stop (v sqrt(m / k)), enough for diagonal pairs to overlap.
  const SquareLattice                    l = square_lattice();
  const double                           h = l.h;
  std::uniform_real_distribution<double> u(-1, 1);
  const ContactMaterial                  cm            = contact_material(1e11);
  int                                    formed_in_run = 0;
  auto                                   run           = [&](int threads) {
    const int old = omp_get_max_threads();
    omp_set_num_threads(threads);
    RigidVoronoiModel model(l.tess, l.x, l.y, l.r, 2650, cm);
    model.parallel_threshold = 0; // threads even on this small model
    model.contacts.parallel_threshold = 0;
    model.damping                     = 0.1;
    const int       installed = model.contacts.n_contacts();
    const double    dt = model.stable_time_step(0.5);
    std::mt19937_64 gen(4);
    for (int i = 0; i < model.n_grains(); ++i)
      {
        model.vx[i] = -40 * (model.x[i] - 6 * h) / (6 * h) + 1.0 * u(gen);
        model.vy[i] = -40 * (model.y[i] - 6 * h) / (6 * h) + 1.0 * u(gen);
        model.omega[i] = 1.0 / h * u(gen);
      }
    for (int s = 0; s < 300; ++s)
      model.step(dt);
    omp_set_num_threads(old);
    formed_in_run = model.contacts.n_contacts() - installed;
    return model;
  };
  const auto one = run(1), two = run(2);
  INFO("contacts formed in the run " << formed_in_run);
  CHECK(formed_in_run > 0);
  CHECK(one.contacts.grain_a == two.contacts.grain_a);
  CHECK(one.contacts.grain_b == two.contacts.grain_b);
  CHECK(one.x == two.x);
  CHECK(one.y == two.y);
  CHECK(one.theta == two.theta);
  CHECK(one.vx == two.vx);
  CHECK(one.fx == two.fx);
  CHECK(one.mz == two.mz);
  CHECK(one.contacts.fn == two.contacts.fn);
  CHECK(one.contacts.fs == two.contacts.fs);
  CHECK(one.contacts.un == two.contacts.un);
  CHECK(one.contacts.edge_length == two.contacts.edge_length);
}

TEST_CASE("Rigid Voronoi new contact: a free collision conserves momentum",
          "[voronoi][rigid_model][new_contacts]")
{
  // Grain A at 1 m/s against B at rest, no damping, no applied force: the
  // contact force acts equal and opposite, so the total momentum is
  // constant to roundoff and, the collision elastic (kn A U, unloading on
  // the same line), so is the kinetic energy after it.
  const auto        g  = two_separate_grains(1.8 * R + 1e-6);
  const auto        cm = contact_material();
  RigidVoronoiModel model(g.tess, g.x, g.y, g.r, 2650, cm);
  model.damping = 0;
  model.vx[0]   = 1.0;
  // No contact yet, so no stable_time_step: 2 sqrt(m / k) of the lighter
  // grain against the whole contact's kn A.
  const double dt = 0.3 * 2 *
                    std::sqrt(std::min(model.mass[0], model.mass[1]) /
                              (cm.kn * 1.6 * R * cm.thickness));
  auto momentum = [&] {
    return std::make_pair(model.mass[0] * model.vx[0] + model.mass[1] * model.vx[1],
                          model.mass[0] * model.vy[0] + model.mass[1] * model.vy[1]);
  };
  const auto   p0      = momentum();
  const double ke0     = model.kinetic_energy();
  bool         touched = false, separated = false;
  for (int s = 0; s < 20000 && !separated; ++s)
    {
      model.step(dt);
      const bool overlap = model.x[1] - model.x[0] < 1.8 * R;
      touched            = touched || overlap;
      separated          = touched && !overlap;
      const auto pk      = momentum();
      // Each step adds dt (F_A + F_B) = 0 up to the roundoff of m v sums:
      // 1e-15 relative per step; 1e-12 covers ~1e3 steps of it.
      CHECK(std::abs(pk.first - p0.first) <= 1e-12 * std::abs(p0.first));
      CHECK(pk.second == 0);
    }
  REQUIRE(touched);
  REQUIRE(separated);
  REQUIRE(model.contacts.n_contacts() == 1);
  INFO("B's share of the momentum " << model.mass[1] * model.vx[1] / p0.first
                                    << ", energy after / before "
                                    << model.kinetic_energy() / ke0);
  CHECK(model.vx[1] > 0.5); // B took a positive share of the momentum
  CHECK(model.omega[0] == 0);
  CHECK(model.omega[1] == 0);
  // Energy within the central-difference error O((omega dt)^2), a few 1e-3
  // at 0.3 of the critical step.
  CHECK(model.kinetic_energy() == Approx(ke0).epsilon(5e-3));
}

TEST_CASE("New-contact search: overlaps once, ascending, inactive grains and pairs "
          "in contact left out, stale after half the skin",
          "[voronoi][new_contacts]")
{
  // Four unit disks on a line (skin 0.2: reach 2.2), grain 3 inactive;
  // pair (0, 1), 2.1 apart, already in contact: no candidate.
  std::vector<double>     x      = {0.4, 2.5, 5, 7.5}, y(4, 0.0), r(4, 1.0);
  const std::vector<char> active = {1, 1, 1, 0};
  NewContactSearch        search;
  search.reset(4);
  search.add_contact(1, 0);
  CHECK(search.in_contact(0, 1));
  search.rebuild(x.data(), y.data(), r.data(), active.data(), 0.2);
  CHECK(search.skin() == 0.2);
  CHECK(search.candidates().empty());
  CHECK(search.new_overlaps(x.data(), y.data(), r.data()).empty());
  // Move 2 and 3 left by 0.45 (more than skin / 2 = 0.1): stale.
  x[2] -= 0.45;
  x[3] -= 0.45;
  CHECK(search.stale(x.data(), y.data(), active.data()));
  search.rebuild(x.data(), y.data(), r.data(), active.data(), 0.2);
  // Within 2.2: (1, 2) at 2.05 (and (0, 1), in contact; 3 is inactive).
  REQUIRE(search.candidates().size() == 1);
  CHECK(search.candidates()[0] == std::make_pair(1, 2));
  CHECK(search.new_overlaps(x.data(), y.data(), r.data()).empty()); // 2.05 > 2
  x[2] -= 0.06; // 1.99 < 2: overlap, a move below skin / 2
  CHECK(!search.stale(x.data(), y.data(), active.data()));
  const auto found = search.new_overlaps(x.data(), y.data(), r.data());
  REQUIRE(found.size() == 1);
  CHECK(found[0] == std::make_pair(1, 2));
  CHECK(search.in_contact(2, 1));
  CHECK(search.new_overlaps(x.data(), y.data(), r.data()).empty()); // never twice
  search.rebuild(x.data(), y.data(), r.data(), active.data(), 0.2);
  CHECK(search.candidates().empty()); // (1, 2) now in contact
}

namespace
{
  /// Grains A (0, 0) and B (2R, 0) share the edge x = R of one tessellation
  /// (both cells 2R x 2R, disks of radius R); grain C (disk 0.8 R, cell 1.6 R
  /// square) lies on the right at xc, with no contact.
  RigidVoronoiModel pair_and_third(double xc)
  {
    const auto ab = laguerre_tessellation({0.0, 2 * R}, {0.0, 0.0}, {R, R},
                                          ClipDomain::rectangle(-R, -R, 3 * R, R));
    const auto c  = laguerre_tessellation(
         {xc}, {0.0}, {0.8 * R},
         ClipDomain::rectangle(xc - 0.8 * R, -0.8 * R, xc + 0.8 * R, 0.8 * R));
    return RigidVoronoiModel(concatenate(ab, c), {0.0, 2 * R, xc}, {0.0, 0.0, 0.0},
                             {R, R, 0.8 * R}, 2650, contact_material());
  }
} // namespace

TEST_CASE("Rigid Voronoi new contact: the time step is derived again and lowered",
          "[voronoi][rigid_model][new_contacts]")
{
  // C approaches B (1e-8 m per step: the disks overlap after the 101st
  // move); when their disks overlap a contact forms and B carries
  // two contacts' springs instead of one, so the estimate over all contacts
  // (RigidVoronoiModel::stable_time_step, per-grain sums) falls below the
  // step derived at the start. StableTimeStep must follow it down at the
  // first update after the formation, and not move before.
  auto model = pair_and_third(3.8 * R + 1.0025e-6);
  REQUIRE(model.contacts.n_contacts() == 1);
  model.vx                                 = {0, 0, -0.1};
  const double                      safety = 0.5;
  StableTimeStep<RigidVoronoiModel> dt(model, safety);
  const double                      start = dt.value();
  REQUIRE(start == model.stable_time_step(safety));
  int formed_at = -1;
  for (int s = 0; s < 200 && formed_at < 0; ++s)
    {
      driven_step(model, 1e-7);
      const bool lowered = dt.update(model);
      if (model.contacts.n_contacts() == 1)
        {
          CHECK_FALSE(lowered);
          CHECK(dt.value() == start);
          continue;
        }
      formed_at = s;
      CHECK(lowered);
    }
  REQUIRE(formed_at > 0);
  REQUIRE(model.contacts.n_contacts() == 2);
  const double all_contacts = model.stable_time_step(safety);
  INFO("time step " << start << " -> " << dt.value() << " (estimate over both contacts "
                    << all_contacts << ")");
  // B's translational sum doubles (equal areas and stiffness on both
  // sides): the estimate drops by a factor of order 1/sqrt(2), far beyond
  // round-off.
  CHECK(all_contacts < 0.95 * start);
  CHECK(dt.value() == all_contacts);
  // Nothing new forms afterwards: the step stays.
  driven_step(model, 1e-7);
  CHECK_FALSE(dt.update(model));
  CHECK(dt.value() == all_contacts);
}

TEST_CASE("Rigid Voronoi time step: a separated contact counts within the cell's reach",
          "[voronoi][rigid_model]")
{
  // When B moves away from A their contact's points sit about the
  // midpoint of the centres, outside both cells. The estimate caps each
  // point's arm at the cell's reach (farthest vertex: sqrt(2) R here), so
  // it no longer depends on how far B has gone; uncapped, the rotational
  // sums grow with the square of the separation and the step falls
  // without bound.
  auto         model    = pair_and_third(10 * R);
  const double touching = model.stable_time_step(0.5);
  model.x[1] += 5 * R;
  const double apart = model.stable_time_step(0.5);
  model.x[1] += 50 * R;
  const double far_apart = model.stable_time_step(0.5);
  INFO("estimate touching " << touching << ", 5 R apart " << apart << ", 55 R apart "
                            << far_apart);
  CHECK(far_apart == Approx(apart).epsilon(1e-12));
  // Touching, A's points sit at arms sqrt(2) R, R, sqrt(2) R with the
  // Lobatto weights 1/6, 2/3, 1/6: K_r = k A (4/3) R^2. Capped, all three
  // arms are sqrt(2) R: K_r = 2 k A R^2, at most 1.5 times as much, so the
  // step is at least 1/sqrt(1.5) = 0.816 of the touching one.
  CHECK(apart <= touching * (1 + 1e-12));
  CHECK(apart >= 0.8 * touching);
}
