// Linear contact-bond and linear parallel-bond laws: elastic response of the
// two-grain test (flat-joint memo §2.1.2-2.1.3, Eq. 56-61), breakage on both
// sides of every strength threshold, and Coulomb slip after breakage.
#include "dem/laws/contact_bond_law.h"
#include "dem/laws/parallel_bond_law.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace demfem::dem;

namespace
{
  // Two grains of radius 6.25 mm, just touching, n along +y (2D) / +z (3D).
  constexpr double grain_R = 6.25e-3;

  template <int dim>
  ContactStep<dim> touching_pair()
  {
    ContactStep<dim> k;
    k.n.setZero();
    k.s.setZero();
    k.t.setZero();
    k.xc.setZero();
    if constexpr (dim == 2)
      {
        k.n << 0, 1;
        k.t << -1, 0; // t = k x n (memo Eq. 4)
      }
    else
      {
        k.s << 1, 0, 0;
        k.t << 0, 1, 0;
        k.n << 0, 0, 1; // n = s x t
      }
    k.gap = 0;
    k.R1  = grain_R;
    k.R2  = grain_R;
    k.dt  = 1e-6;
    return k;
  }

  /// Drives a law through `steps` equal increments; the gap follows d_n.
  template <class Law, int dim>
  struct Driver
  {
    typename Law::Params p;
    ContactStep<dim>     k;
    std::vector<double>  st;
    EventSink            sink;
    ContactForce         f;
    std::vector<int>     event_steps;
    int                  step = 0;

    explicit Driver(const typename Law::Params &params)
        : p(params)
        , k(touching_pair<dim>())
    {
      p.validate("test");
      st.resize(Law::state_size(p));
      Law::install(p, p.prepared(), k, st.data());
    }

    void run(int steps, double dn, double dss, double dst, double dtw, double dbs,
             double dbt)
    {
      for (int i = 0; i < steps; ++i)
        {
          k.d_n     = dn;
          k.d_ss    = dss;
          k.d_st    = dst;
          k.d_twist = dtw;
          k.d_bs    = dbs;
          k.d_bt    = dbt;
          k.gap += dn;
          const std::size_t before = sink.events.size();
          Law::update(p, p.prepared(), k, st.data(), f, sink);
          ++step;
          for (std::size_t e = before; e < sink.events.size(); ++e)
            event_steps.push_back(step);
        }
    }

    int breaks() const
    {
      int n = 0;
      for (const auto &e : sink.events)
        n += e.second.kind == LawEvent::bond_break;
      return n;
    }
  };

  // Memo Eq. 56-57, 62: granite beam E = 29 GPa, nu = 0.15, L = 12.5 mm.
  constexpr double E = 29e9, nu = 0.15, L = 12.5e-3;
  constexpr double pb_kn = E / L;                  // 2.3200e12 N/m^3
  constexpr double pb_ks = E / (2 * (1 + nu) * L); // 1.0087e12 N/m^3

  template <int dim>
  typename ParallelBondLaw<dim>::Params two_grain_pbond()
  {
    typename ParallelBondLaw<dim>::Params p;
    p.linear.kn = 0; // memo Eq. 56: linear force is zero
    p.linear.ks = 0;
    p.pb_kn     = pb_kn;
    p.pb_ks     = pb_ks;
    p.pb_rmul   = 0.8; // R_bar = 5 mm
    p.pb_mcf    = 1;
    p.pb_ten    = 1e20;
    p.pb_coh    = 1e20;
    p.pb_fa     = 0;
    p.bonded    = true;
    return p;
  }

  constexpr int    nsteps = 1000;
  constexpr double tol    = 1e-4; // the memo quotes 5 significant digits
} // namespace

TEST_CASE("parallel bond: two-grain axial load, memo Eq. 59", "[bond]")
{
  Driver<ParallelBondLaw<2>, 2> d2(two_grain_pbond<2>());
  d2.run(nsteps, 1e-3 / nsteps, 0, 0, 0, 0, 0);
  CHECK(d2.f.Fn == Approx(2.3200e7).epsilon(tol));
  CHECK(d2.f.Fst == 0);
  CHECK(d2.f.Mbs == 0);

  Driver<ParallelBondLaw<3>, 3> d3(two_grain_pbond<3>());
  d3.run(nsteps, 1e-3 / nsteps, 0, 0, 0, 0, 0);
  CHECK(d3.f.Fn == Approx(1.8221e5).epsilon(tol));
  CHECK(d3.f.Fss == 0);
  CHECK(d3.f.Fst == 0);
  CHECK(d3.f.Mt == 0);
  CHECK(d3.f.Mbs == 0);
  CHECK(d3.f.Mbt == 0);
  // Bond strain energy 1/2 Fn^2 / (kn_bar A_bar) = 1/2 Fn * 1 mm.
  CHECK(ParallelBondLaw<3>::strain_energy(d3.p, d3.p.prepared(), d3.st.data()) ==
        Approx(0.5 * 1.8221e5 * 1e-3).epsilon(tol));
  CHECK(d2.breaks() + d3.breaks() == 0);
}

TEST_CASE("parallel bond: two-grain twisting load, memo Eq. 60", "[bond]")
{
  Driver<ParallelBondLaw<3>, 3> d(two_grain_pbond<3>());
  d.run(nsteps, 0, 0, 0, 0.2 / nsteps, 0, 0);
  CHECK(d.f.Mt == Approx(-1.9806e2).epsilon(tol));
  CHECK(d.f.Fn == 0);
  CHECK(d.f.Mbs == 0);
  CHECK(d.f.Mbt == 0);
  // Strain energy 1/2 Mt^2 / (ks_bar J_bar) = 1/2 |Mt| 0.2 rad.
  CHECK(ParallelBondLaw<3>::strain_energy(d.p, d.p.prepared(), d.st.data()) ==
        Approx(0.5 * 1.9806e2 * 0.2).epsilon(tol));
  const ContactStiffness s = ParallelBondLaw<3>::stiffness(d.p, d.p.prepared(), d.k, d.st.data());
  CHECK(s.kt == Approx(1.9806e2 / 0.2).epsilon(tol));
}

TEST_CASE("parallel bond: two-grain bending load, memo Eq. 61", "[bond]")
{
  Driver<ParallelBondLaw<2>, 2> d2(two_grain_pbond<2>());
  d2.run(nsteps, 0, 0, 0, 0, 0.4 / nsteps, 0);
  CHECK(d2.f.Mbs == Approx(-7.7333e4).epsilon(tol));
  CHECK(d2.f.Fn == 0);
  CHECK(d2.f.Fst == 0);
  const ContactStiffness s2 = ParallelBondLaw<2>::stiffness(d2.p, d2.p.prepared(), d2.k, d2.st.data());
  CHECK(s2.kb == Approx(7.7333e4 / 0.4).epsilon(tol));
  CHECK(s2.kn == Approx(2.3200e7 / 1e-3).epsilon(tol));

  Driver<ParallelBondLaw<3>, 3> d3(two_grain_pbond<3>());
  d3.run(nsteps, 0, 0, 0, 0, 0, 0.4 / nsteps);
  CHECK(d3.f.Mbt == Approx(-4.5553e2).epsilon(tol));
  CHECK(d3.f.Mbs == 0);
  CHECK(d3.f.Mt == 0);
  CHECK(d3.f.Fn == 0);
  CHECK(d2.breaks() + d3.breaks() == 0);
}

namespace
{
  // Runs N steps of combined loading with the given strengths; returns the
  // driver for inspection.
  template <int dim>
  Driver<ParallelBondLaw<dim>, dim> pbond_run(double ten, double coh, double fa,
                                              double mcf, double dn, double dst,
                                              double dtw, double dbs)
  {
    auto p   = two_grain_pbond<dim>();
    p.pb_ten = ten;
    p.pb_coh = coh;
    p.pb_fa  = fa;
    p.pb_mcf = mcf;
    Driver<ParallelBondLaw<dim>, dim> d(p);
    d.run(nsteps, dn / nsteps, 0, dst / nsteps, dtw / nsteps, dbs / nsteps, 0);
    return d;
  }
} // namespace

TEST_CASE("parallel bond: tensile breakage on both sides of sigma_c", "[bond]")
{
  // 3D, tension 1e-6 m plus bending 1e-3 rad, beta_bar = 0.5:
  // sigma = kn_bar dn + beta kn_bar theta R_bar (the bending term is
  // kn_bar I theta R / I).
  const double R = 5e-3, dn = 1e-6, th = 1e-3, beta = 0.5;
  const double sigma = pb_kn * dn + beta * pb_kn * th * R;
  const double eps   = 1e-6; // 1000 steps: step N-1 is 1e-3 below step N
  {
    auto d = pbond_run<3>(sigma * (1 + eps), 1e20, 0, beta, dn, 0, 0, th);
    CHECK(d.breaks() == 0);
    CHECK(d.f.Fn == Approx(pb_kn * M_PI * R * R * dn).epsilon(1e-9));
  }
  {
    auto d = pbond_run<3>(sigma * (1 - eps), 1e20, 0, beta, dn, 0, 0, th);
    REQUIRE(d.breaks() == 1);
    const LawEvent &e = d.sink.events[0].second;
    CHECK(e.mode == 0);
    CHECK(e.size == Approx(2 * R));
    CHECK(e.strength == sigma * (1 - eps));
    CHECK(d.event_steps[0] == nsteps);
    CHECK(d.st[ParallelBondLaw<3>::s_state] == ParallelBondLaw<3>::broken_ten);
    // Bond force and moment reset; linear part (kn = 0) carries nothing.
    CHECK(d.f.Fn == 0);
    CHECK(d.f.Mbs == 0);
    CHECK(ParallelBondLaw<3>::strain_energy(d.p, d.p.prepared(), d.st.data()) == 0);
    // Further loading does not re-bond.
    d.run(10, dn / nsteps, 0, 0, 0, 0, 0);
    CHECK(d.breaks() == 1);
    CHECK(d.f.Fn == 0);
  }
}

TEST_CASE("parallel bond: shear breakage on both sides of c - sigma tan(phi)", "[bond]")
{
  // 2D, compression dn < 0 and shear: sigma = kn_bar dn < 0,
  // tau = ks_bar |dst|, tau_c = c - sigma tan(phi) > c.
  const double dn = -1e-6, dst = 2e-6, fa = 30;
  const double sigma = pb_kn * dn;
  const double tau   = pb_ks * dst;
  const double eps   = 1e-6;
  // c such that tau_c = tau (1 +- eps).
  auto coh = [&](double f) { return tau * f + sigma * std::tan(fa * M_PI / 180); };
  {
    auto d = pbond_run<2>(1e20, coh(1 + eps), fa, 1, dn, dst, 0, 0);
    CHECK(d.breaks() == 0);
    CHECK(d.f.Fst == Approx(-pb_ks * 2 * 5e-3 * dst).epsilon(1e-9));
  }
  {
    auto d = pbond_run<2>(1e20, coh(1 - eps), fa, 1, dn, dst, 0, 0);
    REQUIRE(d.breaks() == 1);
    const LawEvent &e = d.sink.events[0].second;
    CHECK(e.mode == 1);
    CHECK(e.strength == Approx(tau * (1 - eps)).epsilon(1e-9));
    CHECK(d.event_steps[0] == nsteps);
    CHECK(d.st[ParallelBondLaw<2>::s_state] == ParallelBondLaw<2>::broken_shear);
    CHECK(d.f.Fn == 0);
    CHECK(d.f.Fst == 0);
  }
  // Without friction angle the compression does not help: tau_c = c.
  {
    auto d = pbond_run<2>(1e20, tau * (1 + eps), 0, 1, dn, dst, 0, 0);
    CHECK(d.breaks() == 0);
    auto d2 = pbond_run<2>(1e20, tau * (1 - eps), 0, 1, dn, dst, 0, 0);
    CHECK(d2.breaks() == 1);
  }
  // 3D twist term: tau = beta |Mt| R / J = beta ks_bar theta_t R.
  {
    const double th = 1e-3, tau_t = 0.5 * pb_ks * th * 5e-3;
    auto         d = pbond_run<3>(1e20, tau_t * (1 + eps), 0, 0.5, 0, 0, th, 0);
    CHECK(d.breaks() == 0);
    auto d2 = pbond_run<3>(1e20, tau_t * (1 - eps), 0, 0.5, 0, 0, th, 0);
    CHECK(d2.breaks() == 1);
    CHECK(d2.sink.events[0].second.mode == 1);
  }
}

TEST_CASE("parallel bond: linear part after breakage follows Coulomb", "[bond]")
{
  auto p            = two_grain_pbond<2>();
  p.linear.kn       = 1e8;
  p.linear.ks       = 5e7;
  p.linear.friction = 0.4;
  p.pb_coh          = 1e5; // tiny: breaks in shear almost at once
  Driver<ParallelBondLaw<2>, 2> d(p);
  d.run(100, -1e-7, 0, 0, 0, 0, 0); // compress 1e-5 m: linear Fn = -1000 N
  CHECK(d.breaks() == 0);
  d.run(1000, 0, 0, 1e-7, 0, 0, 0); // shear 1e-4 m: linear trial 5000 N
  CHECK(d.breaks() == 1);
  CHECK(d.sink.events[0].second.mode == 1);
  // Bond gone: total force = linear force, Fn = kn * overlap, |Fs| = mu |Fn|.
  CHECK(d.f.Fn == Approx(-1000).epsilon(1e-9));
  CHECK(d.f.Fst == Approx(-400).epsilon(1e-9));
  CHECK(ParallelBondLaw<2>::slip_energy(d.p, d.p.prepared(), d.st.data()) > 0);
}

// ---------------------------------------------------------------------------
// Linear contact bond.

namespace
{
  ContactBondLaw<2>::Params cbond(double tenf, double shearf)
  {
    ContactBondLaw<2>::Params p;
    p.linear.kn       = 1e8;
    p.linear.ks       = 5e7;
    p.linear.friction = 0.5;
    p.cb_tenf         = tenf;
    p.cb_shearf       = shearf;
    p.bonded          = true;
    return p;
  }
} // namespace

TEST_CASE("contact bond: carries tension, breaks at cb_tenf", "[bond]")
{
  // Opening 1e-5 m in 1000 steps: Fn = kn gap = 1000 N of tension.
  const double fn = 1e8 * 1e-5, eps = 1e-6;
  {
    Driver<ContactBondLaw<2>, 2> d(cbond(fn * (1 + eps), 1e20));
    d.run(nsteps, 1e-5 / nsteps, 0, 0, 0, 0, 0);
    CHECK(d.breaks() == 0);
    CHECK(d.f.Fn == Approx(fn).epsilon(1e-9));
    CHECK(ContactBondLaw<2>::active(d.p, d.p.prepared(), d.st.data(), d.k.gap));
    CHECK_FALSE(ContactBondLaw<2>::deletable(d.p, d.p.prepared(), d.st.data(), d.k.gap));
  }
  {
    Driver<ContactBondLaw<2>, 2> d(cbond(fn * (1 - eps), 1e20));
    d.run(nsteps, 1e-5 / nsteps, 0, 0, 0, 0, 0);
    REQUIRE(d.breaks() == 1);
    const LawEvent &e = d.sink.events[0].second;
    CHECK(e.mode == 0);
    CHECK(e.size == Approx(2 * grain_R));
    CHECK(e.gap == Approx(1e-5));
    CHECK(d.event_steps[0] == nsteps);
    // Broken, open: behaves as linear (no tension) and may be deleted.
    CHECK(d.f.Fn == 0);
    CHECK(ContactBondLaw<2>::deletable(d.p, d.p.prepared(), d.st.data(), d.k.gap));
  }
}

TEST_CASE("contact bond: no slip while bonded, breaks at cb_shearf", "[bond]")
{
  // Compress 1e-5 m (Fn = -1000 N, Coulomb limit 500 N) and shear 2e-5 m in
  // 1000 steps: bonded shear force ks * 2e-5 = 1000 N > mu |Fn|, no slip.
  const double fs = 5e7 * 2e-5, eps = 1e-6;
  {
    Driver<ContactBondLaw<2>, 2> d(cbond(1e20, fs * (1 + eps)));
    d.run(100, -1e-7, 0, 0, 0, 0, 0);
    d.run(nsteps, 0, 0, 2e-5 / nsteps, 0, 0, 0);
    CHECK(d.breaks() == 0);
    CHECK(d.f.Fst == Approx(-fs).epsilon(1e-9));
    CHECK(ContactBondLaw<2>::slip_energy(d.p, d.p.prepared(), d.st.data()) == 0);
  }
  {
    Driver<ContactBondLaw<2>, 2> d(cbond(1e20, fs * (1 - eps)));
    d.run(100, -1e-7, 0, 0, 0, 0, 0);
    d.run(nsteps, 0, 0, 2e-5 / nsteps, 0, 0, 0);
    REQUIRE(d.breaks() == 1);
    CHECK(d.sink.events[0].second.mode == 1);
    CHECK(d.event_steps[0] == 100 + nsteps);
    // After the break the same step is redone by the linear law: Coulomb.
    CHECK(d.f.Fn == Approx(-1000).epsilon(1e-9));
    CHECK(d.f.Fst == Approx(-500).epsilon(1e-9));
    // Continued shearing slides at the Coulomb limit.
    d.run(100, 0, 0, 1e-7, 0, 0, 0);
    CHECK(d.f.Fst == Approx(-500).epsilon(1e-9));
    CHECK(d.breaks() == 1);
    // Slip energy (linear law, trapezoidal): break step Fo = -999 N,
    // F = -500 N, slip = 2e-8 + 499 / ks = 1e-5 m -> 0.5 * 1499 * 1e-5; then
    // 100 steps of 1e-7 m at 500 N -> 5e-3 J.
    CHECK(ContactBondLaw<2>::slip_energy(d.p, d.p.prepared(), d.st.data()) ==
          Approx(0.5 * 1499 * 1e-5 + 5e-3).epsilon(1e-6));
  }
}

TEST_CASE("bond laws: invalid properties throw InputError", "[bond]")
{
  auto bad_pb = [](auto modify) {
    auto p = two_grain_pbond<3>();
    modify(p);
    p.validate("pbond test");
  };
  using P = ParallelBondLaw<3>::Params;
  CHECK_THROWS_AS(bad_pb([](P &p) { p.pb_kn = -1; }), InputError);
  CHECK_THROWS_AS(bad_pb([](P &p) { p.pb_ks = -1; }), InputError);
  CHECK_THROWS_AS(bad_pb([](P &p) { p.pb_rmul = 0; }), InputError);
  CHECK_THROWS_AS(bad_pb([](P &p) { p.pb_mcf = 1.5; }), InputError);
  CHECK_THROWS_AS(bad_pb([](P &p) { p.pb_ten = -1; }), InputError);
  CHECK_THROWS_AS(bad_pb([](P &p) { p.pb_coh = -1; }), InputError);
  CHECK_THROWS_AS(bad_pb([](P &p) { p.pb_fa = 90; }), InputError);
  CHECK_THROWS_AS(bad_pb([](P &p) { p.linear.kn = -1; }), InputError);
  CHECK_THROWS_WITH(bad_pb([](P &p) { p.pb_mcf = 1.5; }), Catch::Contains("pb_mcf") &&
                                                              Catch::Contains("1.5") &&
                                                              Catch::Contains("[0, 1]"));
  CHECK_NOTHROW(bad_pb([](P &p) { p.pb_mcf = 0; }));

  using C     = ContactBondLaw<2>::Params;
  auto bad_cb = [](auto modify) {
    C p = cbond(1, 1);
    modify(p);
    p.validate("cbond test");
  };
  CHECK_THROWS_AS(bad_cb([](C &p) { p.cb_tenf = -1; }), InputError);
  CHECK_THROWS_AS(bad_cb([](C &p) { p.cb_shearf = -1; }), InputError);
  CHECK_THROWS_AS(bad_cb([](C &p) { p.linear.friction = -1; }), InputError);
  CHECK_THROWS_WITH(bad_cb([](C &p) { p.cb_shearf = -2; }),
                    Catch::Contains("cb_shearf") && Catch::Contains("-2"));
  CHECK_NOTHROW(bad_cb([](C &) {}));
}
