// Engine-level tests: contact detection, integration, time step, stability.
#include "dem/engine/model.h"
#include "dem/laws/linear_law.h"

#include <catch2/catch.hpp>

#include <random>
#include <set>

using namespace demfem::dem;

namespace
{
  // Portable uniform deviate (std distributions differ across compilers).
  double uniform(std::mt19937_64 &g, double a, double b)
  {
    return a + (b - a) * (static_cast<double>(g() >> 11) * 0x1.0p-53);
  }

  template <int dim>
  void random_cloud(Model<dim> &m, int n, double box, std::uint64_t seed)
  {
    std::mt19937_64 g(seed);
    for (int i = 0; i < n; ++i)
      {
        Vec<dim> x;
        for (int d = 0; d < dim; ++d)
          x[d] = uniform(g, 0, box);
        m.particles.add(x, uniform(g, 0.5, 1.5), 2650);
      }
  }

  template <int dim>
  void check_detection(std::uint64_t seed)
  {
    Model<dim>   m;
    const int    n   = dim == 2 ? 600 : 500;
    const double box = dim == 2 ? 40.0 : 14.0;
    random_cloud(m, n, box, seed);
    LinearLaw<2>::Params dummy;
    (void)dummy;
    typename LinearLaw<dim>::Params lp;
    lp.kn = 1e6, lp.ks = 1e6;
    m.set_default_law(m.template add_law<LinearLaw<dim>>(lp), -1);
    m.skin = 0.2;
    m.detect_contacts();
    std::set<std::pair<std::uint32_t, std::uint32_t>> found, brute;
    for (int g = 0; g < m.n_groups(); ++g)
      for (std::size_t k = 0; k < m.group(g).size(); ++k)
        found.emplace(m.group(g).end1[k], m.group(g).end2[k]);
    for (std::uint32_t i = 0; i < m.particles.size(); ++i)
      for (std::uint32_t j = i + 1; j < m.particles.size(); ++j)
        if ((m.particles.x[j] - m.particles.x[i]).norm() <
            m.particles.radius[i] + m.particles.radius[j] + m.skin)
          brute.emplace(i, j);
    REQUIRE(brute.size() > static_cast<std::size_t>(n)); // dense enough to matter
    CHECK(found == brute);
  }
} // namespace

TEST_CASE("grid detection finds exactly the brute-force pairs (2D)",
          "[engine][detection]")
{
  for (std::uint64_t seed : {1, 2, 3})
    check_detection<2>(seed);
}

TEST_CASE("grid detection finds exactly the brute-force pairs (3D)",
          "[engine][detection]")
{
  for (std::uint64_t seed : {4, 5})
    check_detection<3>(seed);
}

namespace
{
  /// Head-on undamped collision of two equal spheres with a linear contact.
  template <int dim>
  double collision_energy_ratio(double dt_fraction)
  {
    Model<dim> m;
    Vec<dim>   a = Vec<dim>::Zero(), b = Vec<dim>::Zero();
    b[0] = 2.1;
    m.particles.add(a, 1.0, 1000);
    m.particles.add(b, 1.0, 1000);
    m.particles.v[0][0] = 1.0;
    m.particles.v[1][0] = -1.0;
    typename LinearLaw<dim>::Params lp;
    lp.kn = 1e7, lp.ks = 1e7, lp.friction = 0.5;
    m.set_default_law(m.template add_law<LinearLaw<dim>>(lp), -1);
    m.local_damping   = 0;
    const double mass = m.particles.mass[0];
    m.set_timestep(dt_fraction * std::sqrt(mass / lp.kn));
    const double e0 = m.kinetic_energy();
    for (int s = 0; s < 200000 && m.particles.x[1][0] - m.particles.x[0][0] < 2.2; ++s)
      m.step();
    REQUIRE(m.particles.v[0][0] < 0); // rebounded
    return m.kinetic_energy() / e0;
  }
} // namespace

TEST_CASE("undamped elastic collision conserves kinetic energy", "[engine][linear]")
{
  // Central difference on a linear spring is symplectic; the only energy
  // error comes from the contact onset falling between steps, O(dt / t_c).
  // With dt = 0.02 sqrt(m/k) (t_c = pi sqrt(m/2k) ~ 110 dt) it is < 1e-3.
  CHECK(collision_energy_ratio<2>(0.02) == Approx(1.0).margin(1e-3));
  CHECK(collision_energy_ratio<3>(0.02) == Approx(1.0).margin(1e-3));
  // The error shrinks with the step: halving dt must not make it worse.
  CHECK(std::abs(collision_energy_ratio<3>(0.01) - 1) <=
        std::abs(collision_energy_ratio<3>(0.02) - 1) + 1e-12);
}

namespace
{
  /// A compressed, tightly packed square lattice with linear contacts.
  template <int dim>
  void lattice(Model<dim> &m, int n)
  {
    const double r = 0.5;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < (dim == 3 ? n : 1); ++k)
          {
            Vec<dim> x;
            x[0] = i * 0.99, x[1] = j * 0.99;
            if constexpr (dim == 3)
              x[2] = k * 0.99;
            m.particles.add(x, r, 2650);
          }
    typename LinearLaw<dim>::Params lp;
    lp.kn = 1e8, lp.ks = 5e7, lp.friction = 0.3;
    m.set_default_law(m.template add_law<LinearLaw<dim>>(lp), -1);
    m.local_damping = 0;
    m.skin          = 0.05;
    m.detect_contacts();
  }
} // namespace

TEST_CASE("time step above critical is refused, below critical is stable",
          "[engine][timestep]")
{
  Model<2> probe;
  lattice(probe, 8);
  const double crit = probe.critical_timestep();
  REQUIRE(std::isfinite(crit));
  // Estimate: interior particle with 4 contacts of k = max(kn, ks) = 1e8.
  const double mass = probe.particles.mass[0];
  CHECK(crit == Approx(std::sqrt(mass / 4e8) * std::sqrt(1.0)).epsilon(0.5));

  Model<2> fast;
  lattice(fast, 8);
  fast.set_timestep(1.2 * crit);
  fast.invalidate_contacts();
  CHECK_THROWS_AS(fast.step(), InstabilityError);
  try
    {
      fast.step();
    }
  catch (const InstabilityError &e)
    {
      CHECK_THAT(e.what(), Catch::Contains("critical time step"));
    }

  Model<2> slow;
  lattice(slow, 8);
  slow.set_timestep(0.8 * crit);
  slow.step();
  const double e0 = slow.kinetic_energy() + slow.strain_energy();
  REQUIRE(e0 > 0);
  slow.cycle(2000);
  // Undamped and stable: total energy stays at its initial value (tolerance:
  // central difference energy oscillates by O((w dt)^2) ~ a few percent).
  CHECK(slow.kinetic_energy() + slow.strain_energy() == Approx(e0).epsilon(0.05));
}

TEST_CASE("divergence is detected by the energy monitor when the check is off",
          "[engine][timestep]")
{
  Model<2> m;
  lattice(m, 6);
  // Confine the lattice (fixed rim) so it cannot simply fly apart.
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    {
      const auto &x = m.particles.x[i];
      if (x[0] < 0.1 || x[1] < 0.1 || x[0] > 4.9 || x[1] > 4.9)
        m.particles.fixity[i] = fix_all;
    }
  m.particles.v[14][0] = 1e-3; // a small disturbance
  const double crit    = m.critical_timestep();
  m.check_timestep     = false;
  m.set_timestep(4.0 * crit); // beyond the true central-difference limit
  CHECK_THROWS_AS(m.cycle(5000), InstabilityError);
}

TEST_CASE("contacts within the touching gap count in the critical time step",
          "[engine][timestep]")
{
  // Two disks 1 nm apart (the carved rim's grains sit 1e-7 of their gap off
  // the ring, coupling/region_genesis.cc): open, so the critical step does
  // not see them until they close; with Model::touching_gap above the gap
  // it equals the step of the same pair closed by 1 nm (linear stiffness:
  // independent of the overlap; the lever arm differs by 1e-8 relative).
  auto critical = [](double gap, double touching) {
    Model<2> m;
    m.particles.add(Vec<2>(0, 0), 0.1, 2650);
    m.particles.add(Vec<2>(0.2 + gap, 0), 0.1, 2650);
    LinearLaw<2>::Params lp;
    lp.kn       = 1e8;
    lp.ks       = 5e7;
    const int g = m.add_law<LinearLaw<2>>(lp);
    m.set_default_law(g, g);
    m.touching_gap = touching;
    m.set_timestep(1e-12); // one force pass: the contact's gap, no motion
    m.step();
    return m.critical_timestep();
  };
  const double closed = critical(-1e-9, 0);
  REQUIRE(std::isfinite(closed));
  CHECK(std::isinf(critical(1e-9, 0)));
  CHECK(critical(1e-9, 1e-8) == Approx(closed).epsilon(1e-6));
  CHECK(std::isinf(critical(1e-7, 1e-8))); // farther than the touching gap
}

TEST_CASE("invalid particle input names the property", "[engine][input]")
{
  Particles<3> p;
  CHECK_THROWS_WITH(p.add(Vec<3>::Zero(), -1.0, 2650), Catch::Contains("radius"));
  CHECK_THROWS_WITH(p.add(Vec<3>::Zero(), 1.0, 0.0), Catch::Contains("density"));
}

TEST_CASE("reordering particles by cell does not change the physics", "[engine][reorder]")
{
  auto run = [](bool reorder) {
    Model<2> m;
    random_cloud(m, 400, 25.0, 11);
    LinearLaw<2>::Params lp;
    lp.kn = 1e6, lp.ks = 5e5, lp.friction = 0.5;
    m.set_default_law(m.add_law<LinearLaw<2>>(lp), -1);
    m.gravity = Vec<2>(0, -9.81);
    m.detect_contacts();
    if (reorder)
      m.reorder_by_cell();
    m.set_timestep(1e-4);
    m.cycle(300);
    std::vector<Vec<2>> by_id(m.particles.size());
    for (std::size_t i = 0; i < m.particles.size(); ++i)
      by_id[m.particles.id[i]] = m.particles.x[i];
    return std::pair{by_id, m.n_contacts()};
  };
  const auto [a, na] = run(false);
  const auto [b, nb] = run(true);
  CHECK(na == nb);
  double   moved = 0, diff = 0;
  Model<2> ref;
  random_cloud(ref, 400, 25.0, 11);
  for (std::size_t i = 0; i < a.size(); ++i)
    {
      moved = std::max(moved, (a[i] - ref.particles.x[i]).norm());
      diff  = std::max(diff, (a[i] - b[i]).norm());
    }
  REQUIRE(moved > 1e-3); // the particles did move
  // Only the summation order of contact forces differs: round-off level.
  CHECK(diff <= 1e-9 * moved);
}

#include "dem/laws/flat_joint_law.h"

TEST_CASE("cracks follow the material after breakage (fistPkg §3.4)", "[engine][cracks]")
{
  Model<2> m;
  m.particles.add(Vec<2>(0, 0), 1.0, 2650);
  m.particles.add(Vec<2>(2, 0), 1.0, 2650);
  for (auto &f : m.particles.fixity)
    f = fix_all;
  FlatJointLaw<2>::Params fp;
  fp.Nr = 2, fp.kn = 1e9, fp.ks = 5e8, fp.ten = 1e5, fp.coh = 1e9, fp.bonded = true;
  m.install(0, 1, m.add_law<FlatJointLaw<2>>(fp));
  m.set_timestep(1e-3);
  m.particles.v[1] = Vec<2>(1e-3, 0); // open 1e-6 per step; breaks at 1e-4
  for (int s = 0; s < 400 && m.cracks.empty(); ++s)
    m.step();
  REQUIRE(m.cracks.size() == 2);  // both elements break in tension together
  const auto   before = m.cracks; // geometry at breakage
  const double g_brk  = (m.particles.x[1] - m.particles.x[0]).norm() - 2.0;
  // Move the pair rigidly: turn it by 90 degrees about particle 0 and open
  // the contact by a further 0.1.
  m.particles.x[1] = Vec<2>(0, 2.0 + g_brk + 0.1);
  const auto now   = m.current_cracks();
  for (std::size_t k = 0; k < 2; ++k)
    {
      const auto &c = now[k];
      // Tolerances: the break happens within one step of 1e-6 opening, and
      // g_brk measures the gap at the end of that step (1e-6 absolute).
      CHECK(c.normal[0] == Approx(0).margin(1e-12));
      CHECK(c.normal[1] == Approx(1).epsilon(1e-12));
      CHECK(c.gap == Approx(before[k].gap_break + 0.1).margin(2e-6));
      // The element offset (along t = z x n) turned with the pair: for the
      // original n = +x, t = +y; now n = +y, t = -x.
      // Element centroids sit at rho = +-R/2 (memo Eq. 13, R = 1, Nr = 2).
      CHECK(std::abs(before[k].offset[1]) == Approx(0.5).epsilon(1e-12));
      const double xc_y = 1.0 + 0.5 * (g_brk + 0.1);
      CHECK(c.position[1] == Approx(xc_y).margin(1e-6));
      // Offset rho along +y before the quarter turn, along -x after it.
      CHECK(c.position[0] == Approx(-before[k].offset[1]).margin(1e-12));
    }
}
