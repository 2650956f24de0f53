// Flexible Voronoi model (dem/voronoi/flexible_model.h; seed 004 §2.2-2.3):
// Newton's third law of the contact and element forces, no force under a
// rigid translation, and the flexible model tending to the rigid one as the
// grains' Young's modulus grows.
#include "dem/engine/types.h"
#include "dem/voronoi/flexible_model.h"
#include "dem/voronoi/tessellation.h"

#include "voronoi_test_helpers.h"

#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;
using namespace demfem::dem::voronoi::testing;

TEST_CASE("Flexible Voronoi model: forces balance, rigid translation is force free",
          "[voronoi][flexible]")
{
  // A 3 x 3 lattice of slightly perturbed disks.
  std::vector<double> x, y, r;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      {
        x.push_back((i + 0.5) * 2e-3 + 1e-4 * std::sin(7.0 * (i + 3 * j)));
        y.push_back((j + 0.5) * 2e-3 + 1e-4 * std::cos(5.0 * (i + 3 * j)));
        r.push_back(0.9e-3);
      }
  const auto t = laguerre_tessellation(x, y, r, ClipDomain::rectangle(0, 0, 6e-3, 6e-3));
  FlexibleVoronoiModel model(t, x, y, r, grain_elasticity(50e9, 0.01),
                             elastic_lattice_contacts());
  REQUIRE(model.contacts.n_contacts() >= 12);
  const double dt = model.stable_time_step(0.2);

  SECTION("rigid translation")
  {
    for (int m = 0; m < model.mesh.n_nodes(); ++m)
      {
        model.vx[m] = 0.3;
        model.vy[m] = -0.2;
      }
    for (int i = 0; i < 50; ++i)
      model.step(dt);
    // Interpolated velocities of both grains are the same (sum N = 1): the
    // relative velocity is roundoff (1e-16 m/s) and the contact forces
    // below kn A * 50 dt * 1e-16 m/s; the elements see F = I up to the
    // roundoff eps |x| |grad N| ~ 1e-15 of the positions, i.e. stresses of
    // E 1e-15 and node forces ~1e-9 N. 1e-6 N is a bound with margin,
    // against the ~1e3 N forces of a strain of 1e-4.
    double fmax = 0;
    for (int m = 0; m < model.mesh.n_nodes(); ++m)
      fmax = std::max(fmax, std::hypot(model.fx[m], model.fy[m]));
    INFO("largest node force " << fmax << " N, dt " << dt << " s");
    CHECK(fmax <= 1e-6);
    // Velocities change by at most 50 dt fmax / m_min (1e-10 m/s here).
    double m_min = HUGE_VAL;
    for (double m : model.mesh.mass)
      m_min = std::min(m_min, m);
    for (int m = 0; m < model.mesh.n_nodes(); ++m)
      {
        CHECK(std::abs(model.vx[m] - 0.3) <= 50 * dt * 1e-6 / m_min);
        CHECK(std::abs(model.vy[m] + 0.2) <= 50 * dt * 1e-6 / m_min);
      }
  }
  SECTION("Newton's third law under random motion")
  {
    std::mt19937                           gen(5u);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int m = 0; m < model.mesh.n_nodes(); ++m)
      {
        model.vx[m] = 0.05 * u(gen);
        model.vy[m] = 0.05 * u(gen);
      }
    for (int i = 0; i < 200; ++i)
      {
        model.step(dt);
        double sx = 0, sy = 0, fmax = 0;
        for (int m = 0; m < model.mesh.n_nodes(); ++m)
          {
            sx += model.fx[m];
            sy += model.fy[m];
            fmax = std::max(fmax, std::hypot(model.fx[m], model.fy[m]));
          }
        // Element forces sum to zero per triangle and each contact point
        // gives f to B's nodes and -f to A's (sum N = 1): the total is
        // roundoff of a sum of ~100 forces of size fmax.
        CHECK(std::abs(sx) <= 1e-12 * fmax);
        CHECK(std::abs(sy) <= 1e-12 * fmax);
      }
  }
}

TEST_CASE("Flexible Voronoi model tends to the rigid one as E grows",
          "[voronoi][flexible]")
{
  // Two square grains (disks R = 1 mm at (0, 0) and (2, 0) mm, cells
  // 2 x 2 mm); grain A held, a force F on B's centroid node pushes B
  // against A. Rigid grains: B moves by F / (kn A), A = L t (no rotation by
  // symmetry). Flexible grains add the grain's own compliance ~ F / (E t),
  // so the relative excess over the rigid answer must fall like 1 / E.
  const double              R = 1e-3;
  const std::vector<double> x = {0, 2 * R}, y = {0, 0}, r = {R, R};
  const auto t  = laguerre_tessellation(x, y, r, ClipDomain::rectangle(-R, -R, 3 * R, R));
  const auto cm = elastic_lattice_contacts();
  const double        F = 1e3, A = 2 * R * cm.thickness;
  const double        rigid = F / (cm.kn * A);
  std::vector<double> excess;
  for (double E : {2e10, 2e11, 2e12})
    {
      FlexibleVoronoiModel model(t, x, y, r, grain_elasticity(E, 0.01), cm);
      model.damping = 0.7;
      for (int m = model.mesh.grain_node_offset[0]; m < model.mesh.grain_node_offset[1];
           ++m)
        model.fixed[m] = 1;
      const int cb     = model.centroid_node(1);
      model.fx_ext[cb] = -F;
      const double dt  = model.stable_time_step(0.3);
      // Damped to rest: run until the kinetic energy is 1e-16 of the work
      // F * rigid, then check that it stays at rest.
      int steps = 0;
      for (; steps < 400000; ++steps)
        {
          model.step(dt);
          if (steps > 1000 && model.kinetic_energy() < 1e-16 * F * rigid)
            break;
        }
      REQUIRE(steps < 400000);
      const double delta = model.mesh.x0[cb] - model.x[cb];
      // Static equilibrium: the contact carries F (sum of the point forces).
      double fn = 0;
      for (int p = 0; p < model.contacts.n_points(); ++p)
        fn += model.contacts.fn[p];
      CHECK(-fn == Approx(F).epsilon(1e-6));
      excess.push_back(delta / rigid - 1);
      INFO("E = " << E << ": delta / rigid - 1 = " << excess.back());
      CHECK(excess.back() > 0);
    }
  // Falls like 1 / E: each factor 10 in E divides the excess by 10 (the
  // rest to damped-equilibrium tolerance and the O(1/E^2) terms: 10 %).
  CHECK(excess[1] / excess[0] == Approx(0.1).epsilon(0.1));
  CHECK(excess[2] / excess[1] == Approx(0.1).epsilon(0.1));
  CHECK(excess[2] < 1e-2);
}

TEST_CASE("Flexible Voronoi contact under rigid nodal motion is the rigid contact",
          "[voronoi][flexible]")
{
  // Nodal velocities from rigid-body fields of each grain: the shape
  // functions interpolate them exactly (they are linear), so every local
  // point sees the rigid model's relative velocity, carries the same
  // forces, and the nodal forces of each grain have the rigid model's
  // resultant and moment about the disk centre (the transfer keeps both).
  // Positions are held (small displacements), so the grains stay unstrained.
  const std::vector<double> x = {0, 2.6e-3}, y = {0, 0.3e-3}, r = {1e-3, 1.5e-3};
  const auto                t =
      laguerre_tessellation(x, y, r, ClipDomain::rectangle(-2e-3, -1.5e-3, 5e-3, 2e-3));
  auto cm                    = elastic_lattice_contacts();
  cm.tensile_strength        = 3e6; // strengths low enough to damage some points
  cm.cohesion                = 6e6;
  cm.tensile_fracture_energy = 3 * cm.tensile_elastic_energy();
  cm.shear_fracture_energy   = 3 * cm.shear_elastic_energy();
  FlexibleVoronoiModel flex(t, x, y, r, grain_elasticity(50e9, 0.01), cm);
  RigidVoronoiContacts rigid(cm);
  rigid.add_from_tessellation(t, x, y, r, PointScheme::lobatto3);
  REQUIRE(rigid.n_points() == flex.contacts.n_points());

  std::vector<double>                    vx(2), vy(2), om(2), fx(2), fy(2), mz(2);
  const GrainKinematics                  kin{x.data(),  y.data(),  r.data(),
                            vx.data(), vy.data(), om.data()};
  std::mt19937                           gen(11u);
  std::uniform_real_distribution<double> u(-1, 1);
  int                                    damaged = 0;
  double                                 scale   = 0; // largest point force so far
  for (int i = 0; i < 300; ++i)
    {
      for (int k = 0; k < 2; ++k)
        {
          vx[k] = 2e-10 * u(gen) + (k ? 3e-9 : 0); // drift apart
          vy[k] = 2e-10 * u(gen);
          om[k] = 2e-7 * u(gen);
        }
      for (int k = 0; k < 2; ++k)
        for (int m = flex.mesh.grain_node_offset[k];
             m < flex.mesh.grain_node_offset[k + 1]; ++m)
          {
            // v + omega k x (x_m - x_disk) about the disk centre.
            flex.vx[m] = vx[k] - om[k] * (flex.y[m] - y[k]);
            flex.vy[m] = vy[k] + om[k] * (flex.x[m] - x[k]);
          }
      std::fill(fx.begin(), fx.end(), 0.0);
      std::fill(fy.begin(), fy.end(), 0.0);
      std::fill(mz.begin(), mz.end(), 0.0);
      rigid.update(kin, 1.0, GrainForces{fx.data(), fy.data(), mz.data()});
      flex.compute_forces(1.0);
      for (int p = 0; p < rigid.n_points(); ++p)
        scale = std::max({scale, std::abs(rigid.fn[p]), std::abs(rigid.fs[p])});
      // Same arithmetic up to the interpolation's roundoff: 1e-9 of the
      // largest point force (the velocities are interpolated from nodes
      // 1e-3 m away, ~1e-13 relative; increments accumulate over steps).
      for (int p = 0; p < rigid.n_points(); ++p)
        {
          CHECK(std::abs(flex.contacts.fn[p] - rigid.fn[p]) <= 1e-9 * scale);
          CHECK(std::abs(flex.contacts.fs[p] - rigid.fs[p]) <= 1e-9 * scale);
          CHECK(flex.contacts.crack[p] == rigid.crack[p]);
        }
      for (int k = 0; k < 2; ++k)
        {
          double Fx = 0, Fy = 0, M = 0;
          for (int m = flex.mesh.grain_node_offset[k];
               m < flex.mesh.grain_node_offset[k + 1]; ++m)
            {
              Fx += flex.fx[m];
              Fy += flex.fy[m];
              M += (flex.x[m] - x[k]) * flex.fy[m] - (flex.y[m] - y[k]) * flex.fx[m];
            }
          CHECK(std::abs(Fx - fx[k]) <= 1e-9 * 3 * scale);
          CHECK(std::abs(Fy - fy[k]) <= 1e-9 * 3 * scale);
          CHECK(std::abs(M - mz[k]) <= 1e-9 * 3 * scale * 5e-3);
        }
    }
  int cracked = 0;
  for (int p = 0; p < rigid.n_points(); ++p)
    {
      damaged += rigid.damage_t[p] + rigid.damage_s[p] > 0;
      cracked += rigid.crack[p] != PointCrack::intact;
    }
  // The history reached softening and cracks (opening 9e-7 m against the
  // crack opening 2 G_t / sigma_t = 9e-7 m), not only the elastic range.
  CHECK(damaged == rigid.n_points());
  CHECK(cracked > 0);
}

TEST_CASE("Flexible Voronoi model: 1 and 2 threads give bit-identical results",
          "[voronoi][flexible][threads]")
{
  // Contacts write their points' slots, each grain gathers its nodes'
  // contributions in point order, and grains share no nodes: no sum depends
  // on the thread count. A jittered lattice with short edges merged, points
  // that break, a pressure and a platen.
  const Packing p = jittered(12, 14, 21, 0.15);
  const auto   &x = p.x, &y = p.y, &r = p.r;
  const auto    t = laguerre_tessellation(x, y, r, ClipDomain::rectangle(0, 0, p.W, p.H));
  std::uniform_real_distribution<double> u(-1, 1);
  auto                                   run = [&](int threads) {
    const int old = omp_get_max_threads();
    omp_set_num_threads(threads);
    ContactMaterial m  = elastic_lattice_contacts();
    m.tensile_strength = 2e6; // some points break
    m.cohesion         = 6e6;
    m                  = m.brittle();
    FlexibleVoronoiModel model(t, x, y, r, grain_elasticity(50e9, 0.01), m,
                                                                 PointScheme::lobatto3, FlexibleMeshOptions{0.1});
    model.parallel_threshold = 0; // threads even on this small model
    model.damping = 0.3;
    model.set_pressure(Side::left, 1e6);
    const int top = model.add_platen(Side::top, PlatenLaw::frictional, 0.3);
    model.platens[top].vy = -0.5;
    model.activate_platen(top);
    std::mt19937_64 gen(4);
    for (int k = 0; k < model.mesh.n_nodes(); ++k)
      {
        model.vx[k] = 1.0 * u(gen);
        model.vy[k] = 1.0 * u(gen);
      }
    const double dt = model.stable_time_step(0.5);
    for (int s = 0; s < 300; ++s)
      model.step(dt);
    omp_set_num_threads(old);
    return model;
  };
  const auto one = run(1), two = run(2);
  int        cracked = 0;
  for (PointCrack k : one.contacts.crack)
    cracked += k == PointCrack::tensile || k == PointCrack::shear;
  CHECK(cracked > 0); // the law's branches were exercised
  CHECK(one.x == two.x);
  CHECK(one.y == two.y);
  CHECK(one.vx == two.vx);
  CHECK(one.fx == two.fx);
  CHECK(one.fy == two.fy);
  CHECK(one.contacts.fs == two.contacts.fs);
  CHECK(one.contacts.damage_t == two.contacts.damage_t);
  CHECK(one.pp_fn == two.pp_fn);
}

TEST_CASE("Flexible Voronoi model: measure the thread speed-up",
          "[.measure][voronoi][flexible][threads]")
{
  // By hand (docs/voronoi.md, "Threads"): seconds per grain-step of a
  // 64 x 64 jittered lattice, elastic, random velocities, 1 and 2 threads.
  const Packing p = jittered(64, 64, 5, 0.15);
  const auto   &x = p.x, &y = p.y, &r = p.r;
  const auto    t = laguerre_tessellation(x, y, r, ClipDomain::rectangle(0, 0, p.W, p.H));
  std::mt19937_64                        rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int threads : {1, 2, 1, 2})
    {
      const int old = omp_get_max_threads();
      omp_set_num_threads(threads);
      FlexibleVoronoiModel model(t, x, y, r, grain_elasticity(50e9, 0.01),
                                 elastic_lattice_contacts());
      model.parallel_threshold = 0;
      for (int k = 0; k < model.mesh.n_nodes(); ++k)
        {
          model.vx[k] = 1e-3 * u(rng);
          model.vy[k] = 1e-3 * u(rng);
        }
      const double dt    = model.stable_time_step(0.5);
      const double start = omp_get_wtime();
      for (int s = 0; s < 200; ++s)
        model.step(dt);
      const double sec = omp_get_wtime() - start;
      omp_set_num_threads(old);
      std::cout << threads << " threads: " << sec / (200.0 * model.n_grains()) * 1e6
                << " us per grain-step\n";
    }
}
