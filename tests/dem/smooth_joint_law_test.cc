// Smooth-joint law (seed 001): dilation (Eq. 12), breakage (Eq. 13-15),
// sliding along a dipping joint (Eq. 3-6), surface assignment by the sign of
// n_c . n_j, energies (Eq. 16-17) and property validation.
#include "dem/laws/smooth_joint_law.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace demfem::dem;

namespace
{
  using SJ2 = SmoothJointLaw<2>;
  using SJ3 = SmoothJointLaw<3>;

  // R1 = R2 = 10 mm, lambda = 1: R = 10 mm, A = 2 R = 0.02 m^2 (2D strip).
  constexpr double R = 0.01, A2 = 2 * R;

  double rad(double deg) { return deg * M_PI / 180; }

  /// 2D pair with contact normal at angle `a` from +x (t = k x n).
  ContactStep<2> pair2(double a)
  {
    ContactStep<2> k;
    k.n << std::cos(a), std::sin(a);
    k.t << -std::sin(a), std::cos(a);
    k.s.setZero();
    k.xc.setZero();
    k.gap = 0;
    k.R1 = k.R2 = R;
    return k;
  }

  SJ2::Params base2()
  {
    SJ2::Params p;
    p.sj_kn   = 1e10; // kn A = 2e8 N/m
    p.sj_ks   = 5e9;  // ks A = 1e8 N/m
    p.sj_rmul = 1;
    return p;
  }

  template <int dim>
  struct Driver
  {
    using Law = SmoothJointLaw<dim>;
    typename Law::Params p;
    ContactStep<dim>     k;
    std::vector<double>  st;
    EventSink            sink;
    ContactForce         f;
    std::vector<int>     event_steps;
    int                  step = 0;

    Driver(const typename Law::Params &params, const ContactStep<dim> &geo)
        : p(params)
        , k(geo)
    {
      p.validate("test");
      st.resize(Law::state_size(p));
      Law::install(p, p.prepared(), k, st.data());
    }

    /// `steps` equal increments (d_n, d_ss, d_st); the contact gap follows d_n.
    void run(int steps, double dn, double dss, double dst)
    {
      for (int i = 0; i < steps; ++i)
        {
          k.d_n  = dn;
          k.d_ss = dss;
          k.d_st = dst;
          k.gap += dn;
          const std::size_t before = sink.events.size();
          Law::update(p, p.prepared(), k, st.data(), f, sink);
          ++step;
          for (std::size_t e = before; e < sink.events.size(); ++e)
            event_steps.push_back(step);
        }
    }

    double   fn() const { return st[Law::s_fn]; }
    Vec<dim> fs() const { return Eigen::Map<const Vec<dim>>(st.data() + Law::s_fs); }
    Vec<dim> nj() const { return Eigen::Map<const Vec<dim>>(st.data() + Law::s_nj); }
    Vec<dim> us() const { return Eigen::Map<const Vec<dim>>(st.data() + Law::s_us); }
    int      count(LawEvent::Kind kind) const
    {
      int n = 0;
      for (const auto &e : sink.events)
        n += e.second.kind == kind;
      return n;
    }
  };

  constexpr double tight = 1e-9; // pure arithmetic, round-off only
} // namespace

TEST_CASE("smooth joint: dilation while slipping, seed Eq. 12", "[smoothjoint]")
{
  auto p    = base2();
  p.sj_fric = 0.5;
  p.sj_da   = 10;
  // Horizontal joint (dip 0: n_j = +y) and contact normal +y, t = -x.
  Driver<2> d(p, pair2(M_PI / 2));
  d.run(100, -1e-7, 0, 0); // close 1e-5 m: Fn = -kn A 1e-5
  CHECK(d.fn() == Approx(-2000).epsilon(tight));
  CHECK(d.count(LawEvent::slip_start) == 0);
  // One shear step of 2e-5 m along +x (d_st < 0 since t = -x):
  // |Fs*| = ks A 2e-5 = 2000 N, Fs^mu = 0.5 * 2000 = 1000 N, so
  // Fn = -2000 - (2000 - 1000) / ks * kn * tan(10 deg) (compression grows).
  d.run(1, 0, 0, -2e-5);
  const double fn1 = -2000 - (2000.0 - 1000.0) / 5e9 * 1e10 * std::tan(rad(10));
  CHECK(d.fn() == Approx(fn1).epsilon(tight));
  CHECK(fn1 == Approx(-2352.653961).epsilon(1e-9));
  CHECK(d.fs()[0] == Approx(-1000).epsilon(tight)); // Coulomb, Eq. 10
  CHECK(d.fs()[1] == 0);
  CHECK(d.count(LawEvent::slip_start) == 1);
  // Contact force (n = n_j, t = -x): Fn_c = Fn, Fst = Fs . t = +1000.
  CHECK(d.f.Fn == Approx(fn1).epsilon(tight));
  CHECK(d.f.Fst == Approx(1000).epsilon(tight));

  // Steady sliding: with Fs = mu |Fn| the elastic shear also grows, so
  // d|Fn|/du = kn A tan(psi) / (1 + mu tan(psi) kn / ks) (Eq. 12 per step;
  // the step-to-step transient decays as (mu tan(psi) kn/ks)^i = 0.18^i).
  d.run(500, 0, 0, -1e-8);
  const double fa = d.fn();
  d.run(499, 0, 0, -1e-8);
  const double fb = d.fn();
  d.run(1, 0, 0, -1e-8);
  const double slope =
      2e8 * std::tan(rad(10)) / (1 + 0.5 * std::tan(rad(10)) * 2) * 500 * 1e-8;
  CHECK(fa - d.fn() == Approx(slope).epsilon(1e-6));
  // Eq. 9-10: the limit uses Fn of Eq. 7, i.e. before this step's dilation.
  CHECK(d.fs()[0] == Approx(0.5 * fb).epsilon(tight));
  // The dilation of the big step raised the limit to 0.5 * 2352.65 = 1176.3 N
  // above Fs = 1000 N: the joint sticks (slip_end at step 102) until the
  // trial force 1000 + 1 N/step exceeds it, at step 101 + 177 = 278.
  REQUIRE(d.sink.events.size() == 3);
  CHECK(d.sink.events[1].second.kind == LawEvent::slip_end);
  CHECK(d.event_steps[1] == 102);
  CHECK(d.sink.events[2].second.kind == LawEvent::slip_start);
  CHECK(d.event_steps[2] == 278);
}

namespace
{
  // Bonded horizontal joint loaded in tension then examined.
  Driver<2> bonded_pull(double ten, double gap)
  {
    auto p    = base2();
    p.bonded  = true;
    p.sj_ten  = ten;
    p.sj_coh  = 1e20;
    p.sj_fric = 0.3;
    Driver<2> d(p, pair2(M_PI / 2));
    d.run(1000, gap / 1000, 0, 0);
    return d;
  }
} // namespace

TEST_CASE("smooth joint: tensile breakage, seed Eq. 13-14", "[smoothjoint]")
{
  // Opening 1e-5 m: Fn = kn A 1e-5 = 2000 N, sigma = Fn / A = 1e5 Pa.
  const double eps = 1e-6; // step 999 is 1e-3 below step 1000
  {
    auto d = bonded_pull(1e5 * (1 + eps), 1e-5);
    CHECK(d.count(LawEvent::bond_break) == 0);
    CHECK(d.fn() == Approx(2000).epsilon(tight));
    CHECK(d.f.Fn == Approx(2000).epsilon(tight)); // tension carried
    CHECK(SJ2::strain_energy(d.p, d.p.prepared(), d.st.data()) ==
          Approx(0.5 * 2000 * 1e-5).epsilon(tight));
  }
  auto d = bonded_pull(1e5 * (1 - eps), 1e-5);
  REQUIRE(d.count(LawEvent::bond_break) == 1);
  const LawEvent &e = d.sink.events[0].second;
  CHECK(e.mode == 0);
  CHECK(e.size == Approx(2 * R));
  CHECK(e.strength == 1e5 * (1 - eps));
  CHECK(e.gap == Approx(1e-5).epsilon(tight));
  CHECK(d.event_steps[0] == 1000);
  CHECK(d.st[SJ2::s_state] == SJ2::broken_ten);
  CHECK(d.fn() == 0);
  CHECK(d.f.Fn == 0);
  // Unbonded: closing from g_j = 1e-5 to -8e-6 in steps of 3e-8 (g_j = 0 is
  // crossed inside step 334): only the part with g_j < 0 is elastic, so
  // Fn = -kn A 8e-6 = -1600 N exactly.
  d.run(600, -3e-8, 0, 0);
  CHECK(d.st[SJ2::s_gap] == Approx(-8e-6).epsilon(1e-9));
  CHECK(d.fn() == Approx(-1600).epsilon(1e-8));
  // Reopening past g_j = 0 releases it completely.
  d.run(7, 2e-6, 0, 0);
  CHECK(d.fn() == 0);
  CHECK(d.count(LawEvent::bond_break) == 1);
}

namespace
{
  // Bonded horizontal joint: normal loading dn, then shear 1e-5 m along +x.
  Driver<2> bonded_shear(double coh, double fa, double dn)
  {
    auto p    = base2();
    p.bonded  = true;
    p.sj_ten  = 1e20;
    p.sj_coh  = coh;
    p.sj_fa   = fa;
    p.sj_fric = 0.3;
    p.sj_da   = 10; // must not act in the breaking step
    Driver<2> d(p, pair2(M_PI / 2));
    d.run(1000, dn / 1000, 0, 0);
    d.run(1000, 0, 0, -1e-8);
    return d;
  }
} // namespace

TEST_CASE("smooth joint: shear breakage, seed Eq. 13, 15", "[smoothjoint]")
{
  // Compression 1e-5 m: Fn = -2000 N, sigma = -1e5 Pa; shear: |Fs*| = 1000 N,
  // tau = 5e4 Pa; tau_c = c - sigma tan(20 deg) = c + 36397 Pa.
  const double eps = 1e-6, t20 = std::tan(rad(20));
  auto         coh = [&](double f) { return 5e4 * f - 1e5 * t20; };
  {
    auto d = bonded_shear(coh(1 + eps), 20, -1e-5);
    CHECK(d.count(LawEvent::bond_break) == 0);
    CHECK(d.fs()[0] == Approx(-1000).epsilon(tight)); // Eq. 15, no slip
    CHECK(d.fn() == Approx(-2000).epsilon(tight));
  }
  {
    auto d = bonded_shear(coh(1 - eps), 20, -1e-5);
    REQUIRE(d.count(LawEvent::bond_break) == 1);
    const LawEvent &e = d.sink.events[0].second;
    CHECK(e.mode == 1);
    CHECK(e.strength == Approx(5e4 * (1 - eps)).epsilon(tight));
    CHECK(d.event_steps[0] == 2000);
    CHECK(d.st[SJ2::s_state] == SJ2::broken_shear);
    // Broken in compression: Fs limited to mu |Fn| = 600 N, Fn unchanged
    // (no dilation in the breaking step), slip starts.
    CHECK(d.fn() == Approx(-2000).epsilon(tight));
    CHECK(d.fs()[0] == Approx(-600).epsilon(tight));
    CHECK(d.count(LawEvent::slip_start) == 1);
    // Slip energy of the breaking step (Eq. 17): Fs_o = -999, Fs = -600,
    // slip part 1e-8 + (-600 + 999) / (ks A) = 4.0e-6 m.
    const double us = 1e-8 + 399.0 / 1e8;
    CHECK(SJ2::slip_energy(d.p, d.p.prepared(), d.st.data()) ==
          Approx(0.5 * (999 + 600) * us).epsilon(1e-8));
    // Sliding on afterwards is unbonded: dilation now increases compression.
    d.run(10, 0, 0, -1e-8);
    CHECK(d.fn() < -2000);
  }
  // Broken in shear while in tension: everything reset (Eq. 14).
  {
    // Opening 5e-6 m: Fn = +1000 N, sigma = 5e4 Pa; tau_c = c - 5e4 tan 20.
    auto d = bonded_shear(5e4 * (1 + eps) + 5e4 * t20, 20, 5e-6);
    CHECK(d.count(LawEvent::bond_break) == 0);
    CHECK(d.fn() == Approx(1000).epsilon(tight));
    auto d2 = bonded_shear(5e4 * (1 - eps) + 5e4 * t20, 20, 5e-6);
    REQUIRE(d2.count(LawEvent::bond_break) == 1);
    CHECK(d2.sink.events[0].second.mode == 1);
    CHECK(d2.fn() == 0);
    CHECK(d2.fs().norm() == 0);
    CHECK(d2.count(LawEvent::slip_start) == 0);
  }
}

TEST_CASE("smooth joint: pair across a 30 deg dipping joint slides along the joint",
          "[smoothjoint]")
{
  auto p    = base2();
  p.sj_ks   = 1e10; // kn A = ks A = 2e8 N/m
  p.sj_fric = 0.2;
  p.dip     = 30;                     // n_j = (sin 30, cos 30)
  Driver<2>    d(p, pair2(M_PI / 2)); // contact normal +y: n_c . n_j > 0
  const Vec<2> nj(0.5, std::sqrt(3.0) / 2), tj(std::sqrt(3.0) / 2, -0.5);
  CHECK((d.nj() - nj).norm() < 1e-15);
  // Press piece 2 towards piece 1 along the contact normal by D = 1e-5 m.
  const double D = 1e-5;
  d.run(1000, -D / 1000, 0, 0);
  // Eq. 3: joint-normal part -D cos 30 (closing), shear part D sin 30 along
  // the joint tangent t_j (down-dip), NOT along the contact normal.
  CHECK(d.st[SJ2::s_gap] == Approx(-D * nj[1]).epsilon(tight));
  CHECK(d.us()[0] == Approx(0.5 * D * tj[0]).epsilon(tight));
  CHECK(d.us()[1] == Approx(0.5 * D * tj[1]).epsilon(tight));
  CHECK(std::fabs(cross2(d.us(), tj)) < 1e-12 * D);
  const double fn = -2e8 * D * nj[1]; // -1732.05 N
  CHECK(d.fn() == Approx(fn).epsilon(tight));
  // Shear demand ks A D/2 = 1000 N > mu |Fn| = 346 N: it slides from the
  // first step; Fs opposes the sliding of piece 2 (along -t_j).
  const double fs = 0.2 * -fn;
  CHECK(d.fs().dot(tj) == Approx(-fs).epsilon(tight));
  CHECK(std::fabs(cross2(d.fs(), tj)) < 1e-9 * fs);
  CHECK(d.count(LawEvent::slip_start) == 1);
  // Contact force on piece 2: F = -Fn n_j + Fs in contact-plane components
  // (n = +y, t = -x).
  const Vec<2> F = -fn * nj - fs * tj;
  CHECK(d.f.Fn == Approx(-F[1]).epsilon(tight));
  CHECK(d.f.Fst == Approx(-F[0]).epsilon(tight));
  CHECK(d.f.Fst ==
        Approx(-(1732.0508 * 0.5 - 346.41016 * std::sqrt(3.0) / 2)).epsilon(1e-7));
  // Energies: strain Eq. 16 (with A); slip Eq. 17 summed over equal steps
  // with Fs growing linearly: E = 1/2 |Fs| (D/2 - |Fs| / (ks A)).
  CHECK(SJ2::strain_energy(d.p, d.p.prepared(), d.st.data()) ==
        Approx(0.5 * (fn * fn + fs * fs) / 2e8).epsilon(tight));
  CHECK(SJ2::slip_energy(d.p, d.p.prepared(), d.st.data()) ==
        Approx(0.5 * fs * (0.5 * D - fs / 2e8)).epsilon(1e-8));
}

TEST_CASE("smooth joint: surfaces assigned by the sign of n_c . n_j", "[smoothjoint]")
{
  auto p   = base2();
  p.sj_ks  = 1e10; // isotropic joint: F = -kn A (relative displacement)
  p.bonded = true;
  p.sj_ten = p.sj_coh = 1e20;
  p.dip               = 30;
  const Vec<2> nj(0.5, std::sqrt(3.0) / 2);
  const double D = 1e-5;
  // Piece 2 above the joint (n_c = +y): n_j kept; pulling apart = tension.
  Driver<2> up(p, pair2(M_PI / 2));
  up.run(1000, D / 1000, 0, 0);
  CHECK((up.nj() - nj).norm() < 1e-15);
  CHECK(up.fn() == Approx(2e8 * D * nj[1]).epsilon(tight));
  // Piece 2 below (n_c = -y, n_c . n_j < 0): n_j flipped for this contact,
  // so pulling the pieces apart is again joint tension, not compression.
  Driver<2> down(p, pair2(-M_PI / 2));
  CHECK((down.nj() + nj).norm() < 1e-15);
  down.run(1000, D / 1000, 0, 0);
  CHECK(down.fn() == Approx(2e8 * D * nj[1]).epsilon(tight));
  CHECK(down.st[SJ2::s_gap] > 0);
  // Isotropic springs: contact force = kn A D of tension along n_c.
  CHECK(down.f.Fn == Approx(2e8 * D).epsilon(tight));
  CHECK(std::fabs(down.f.Fst) < 1e-9 * 2e8 * D);
  // n_c . n_j = 0 counts as surface 2 (>= 0): no flip.
  Driver<2> side(p, pair2(-M_PI / 6)); // n_c = (cos 30, -sin 30) = t_j
  CHECK((side.nj() - nj).norm() < 1e-15);
}

TEST_CASE("smooth joint: 3D joint normal, shear components, activity", "[smoothjoint]")
{
  SJ3::Params p;
  p.dip          = 30;
  p.ddir         = 60;
  const Vec<3> n = SJ3::joint_normal(p);
  CHECK(n[0] == Approx(0.5 * std::sqrt(3.0) / 2).epsilon(1e-14)); // Eq. 1
  CHECK(n[1] == Approx(0.25).epsilon(1e-14));
  CHECK(n[2] == Approx(std::sqrt(3.0) / 2).epsilon(1e-14));

  // Horizontal joint, contact normal +z (s = x, t = y): A = pi R^2.
  p.dip      = 0;
  p.ddir     = 0;
  p.sj_kn    = 1e10;
  p.sj_ks    = 5e9;
  p.sj_fric  = 1;
  p.sj_large = true;
  ContactStep<3> k;
  k.s << 1, 0, 0;
  k.t << 0, 1, 0;
  k.n << 0, 0, 1;
  k.xc.setZero();
  k.gap = 0;
  k.R1 = k.R2 = R;
  Driver<3> d(p, k);
  CHECK(SJ3::active(d.p, d.p.prepared(), d.st.data(), 0.0) == false);
  CHECK(SJ3::deletable(d.p, d.p.prepared(), d.st.data(), 0.0));
  const double A = M_PI * R * R;
  d.run(100, -1e-7, 0, 0);
  d.run(100, 0, 3e-8, -4e-8);
  CHECK(d.f.Fn == Approx(-1e10 * A * 1e-5).epsilon(tight));
  CHECK(d.f.Fss == Approx(-5e9 * A * 3e-6).epsilon(tight));
  CHECK(d.f.Fst == Approx(5e9 * A * 4e-6).epsilon(tight));
  CHECK(d.f.Mt == 0);
  CHECK(SJ3::active(d.p, d.p.prepared(), d.st.data(), -1e-5));
  CHECK_FALSE(SJ3::deletable(d.p, d.p.prepared(), d.st.data(), -1e-5));
  const ContactStiffness s = SJ3::stiffness(d.p, d.p.prepared(), d.k, d.st.data());
  CHECK(s.kn == Approx(1e10 * A).epsilon(tight));
  CHECK(s.ks == Approx(5e9 * A).epsilon(tight));
  // Small-strain mode: always active, never deletable.
  d.p.sj_large = false;
  CHECK(SJ3::active(d.p, d.p.prepared(), d.st.data(), 1.0));
  CHECK_FALSE(SJ3::deletable(d.p, d.p.prepared(), d.st.data(), 1.0));
}

TEST_CASE("smooth joint: invalid properties throw InputError", "[smoothjoint]")
{
  using P  = SJ3::Params;
  auto bad = [](auto modify) {
    P p;
    modify(p);
    p.validate("sj test");
  };
  CHECK_NOTHROW(bad([](P &) {}));
  CHECK_THROWS_AS(bad([](P &p) { p.sj_kn = -1; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.sj_ks = -1; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.sj_fric = -0.1; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.sj_da = 90; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.sj_da = -1; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.sj_ten = -1; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.sj_coh = -1; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.sj_fa = 90; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.sj_rmul = 0; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.dip = 360.5; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.dip = -1; }), InputError);
  CHECK_THROWS_AS(bad([](P &p) { p.ddir = 181; }), InputError);
  CHECK_NOTHROW(bad([](P &p) {
    p.dip  = 360;
    p.ddir = 180;
  }));
  CHECK_THROWS_WITH(bad([](P &p) { p.sj_fa = 95; }), Catch::Contains("sj_fa") &&
                                                         Catch::Contains("95") &&
                                                         Catch::Contains("[0, 90)"));
}
