// Flat-joint law (memo 000 §1.4-1.13) driven directly with contact-plane
// increments; expected numbers from memo §2.1 (Eq. 53-66) and closed forms.
#include "dem/laws/flat_joint_law.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace demfem::dem;

namespace
{
  // Memo §2.1: E = 29 GPa, nu = 0.15, grains R = 6.25 mm, lambda = 0.8.
  constexpr double E_granite = 29e9, nu_granite = 0.15, R_grain = 6.25e-3;

  template <int dim>
  ContactStep<dim> geometry()
  {
    ContactStep<dim> k;
    k.R1 = k.R2 = R_grain;
    k.n.setZero();
    k.n[1] = 1; // n = +y
    k.s.setZero();
    k.t.setZero();
    if constexpr (dim == 3)
      {
        k.s[0] = 1;  // s = +x
        k.t[2] = -1; // t = -z, so n = s x t
      }
    else
      k.t[0] = -1; // t = k x n
    k.dt = 1;
    return k;
  }

  template <int dim>
  typename FlatJointLaw<dim>::Params memo_params(int Nr, int Nal)
  {
    typename FlatJointLaw<dim>::Params p;
    p.Nr     = Nr;
    p.Nal    = Nal;
    p.rmul   = 0.8;
    p.kn     = E_granite / (2 * R_grain);                        // 2.32e12
    p.ks     = E_granite / (2 * (1 + nu_granite) * 2 * R_grain); // 1.0087e12
    p.ten    = 1e20;
    p.coh    = 1e20;
    p.fa     = 0;
    p.fric   = 0;
    p.bonded = true;
    p.validate("test");
    return p;
  }

  /// A contact driven by increments; keeps state, last force and events.
  template <int dim>
  struct Driver
  {
    using Law = FlatJointLaw<dim>;
    typename Law::Params p;
    ContactStep<dim>     k = geometry<dim>();
    std::vector<double>  st;
    ContactForce         f;
    EventSink            sink;

    explicit Driver(const typename Law::Params &pp) : p(pp)
    {
      st.resize(Law::state_size(p));
      Law::install(p, p.prepared(), k, st.data());
    }
    /// Apply a total motion in n equal increments.
    void move(double dn, double dss, double dst, double dtw, double dbs, double dbt,
              int n = 1000)
    {
      k.d_n = dn / n, k.d_ss = dss / n, k.d_st = dst / n;
      k.d_twist = dtw / n, k.d_bs = dbs / n, k.d_bt = dbt / n;
      for (int i = 0; i < n; ++i)
        Law::update(p, p.prepared(), k, st.data(), f, sink);
    }
    int count(LawEvent::Kind kind) const
    {
      int c = 0;
      for (auto &e : sink.events)
        c += e.second.kind == kind;
      return c;
    }
  };

  double max_abs(std::initializer_list<double> v)
  {
    double m = 0;
    for (double x : v)
      m = std::max(m, std::abs(x));
    return m;
  }
} // namespace

TEST_CASE("flatjoint: deformability and properties of memo §2.1", "[flatjoint]")
{
  ContactGeometry<3> g = geometry<3>();
  auto d = FlatJointLaw<3>::deformability(E_granite, 2 * (1 + nu_granite), g);
  CHECK(d.kn == Approx(2.3200e12).epsilon(1e-12));
  CHECK(d.ks == Approx(1.0087e12).epsilon(1e-4)); // memo gives 5 digits
  ContactGeometry<3> w = g;
  w.ball_wall          = true; // L = R1 (Eq. 40)
  CHECK(FlatJointLaw<3>::deformability(E_granite, 0, w).kn == Approx(2 * 2.32e12));
  CHECK(FlatJointLaw<3>::deformability(E_granite, 0, w).ks == 0);

  Driver<3> c(memo_params<3>(2, 8));
  CHECK(FlatJointLaw<3>::radius(c.st.data()) == Approx(5e-3).epsilon(1e-14)); // Eq. 30
  CHECK(FlatJointLaw<3>::element_count(c.p) == 16);
  CHECK(FlatJointLaw<3>::bonded_count(c.p, c.st.data()) == 16);
  double A = 0, S = 0, T = 0;
  for (int e = 0; e < 16; ++e)
    {
      const double a = FlatJointLaw<3>::element_area(c.p, c.st.data(), e);
      auto         r = FlatJointLaw<3>::element_centroid(c.p, c.st.data(), e);
      A += a, S += a * r[0], T += a * r[1];
    }
  CHECK(A == Approx(M_PI * 25e-6).epsilon(1e-13)); // elements tile the disk
  CHECK(std::abs(S) < 1e-20);                      // centroid of the disk at 0
  CHECK(std::abs(T) < 1e-20);
  // Eq. 41-42
  auto ks = FlatJointLaw<3>::stiffness(c.p, c.p.prepared(), c.k, c.st.data());
  CHECK(ks.kn == Approx(c.p.kn * M_PI * 25e-6));
  CHECK(ks.kt == Approx(c.p.ks * 0.5 * M_PI * std::pow(5e-3, 4)));
  Driver<2> c2(memo_params<2>(4, 1));
  auto      ks2 = FlatJointLaw<2>::stiffness(c2.p, c2.p.prepared(), c2.k, c2.st.data());
  CHECK(ks2.kn == Approx(c2.p.kn * 1e-2));
  CHECK(ks2.kb == Approx(c2.p.kn * 2.0 / 3.0 * 125e-9));
  CHECK(ks2.kt == 0);
}

TEST_CASE("flatjoint: 2D axial and bending, memo Eq. 64 and 66", "[flatjoint]")
{
  Driver<2> a(memo_params<2>(4, 1));
  a.move(1e-3, 0, 0, 0, 0, 0);
  CHECK(a.f.Fn == Approx(2.3200e7).epsilon(1e-4));
  CHECK(max_abs({a.f.Fss, a.f.Fst, a.f.Mt, a.f.Mbs, a.f.Mbt}) < 1e-6 * a.f.Fn);
  // strain energy of a uniform stress = F^2 / (2 kn A) exactly (Eq. 36-37)
  const double EA = a.p.kn * 1e-2;
  CHECK(FlatJointLaw<2>::strain_energy(a.p, a.p.prepared(), a.st.data()) ==
        Approx(0.5 * a.f.Fn * a.f.Fn / EA).epsilon(1e-12));

  for (int Nr : {1, 2, 4, 7})
    {
      Driver<2> b(memo_params<2>(Nr, 1));
      b.move(0, 0, 0, 0, 0.4, 0);
      INFO("Nr = " << Nr);
      // exact integrals (Eq. 44-49): closed form -kn I theta_bs for every Nr
      const double I = 2.0 / 3.0 * 125e-9;
      CHECK(b.f.Mbs == Approx(-b.p.kn * I * 0.4).epsilon(1e-12));
      CHECK(b.f.Mbs == Approx(-7.7333e4).epsilon(1e-4));
      CHECK(max_abs({b.f.Fn, b.f.Fss, b.f.Fst, b.f.Mt, b.f.Mbt}) <
            1e-6 * std::abs(b.f.Mbs));
      CHECK(FlatJointLaw<2>::strain_energy(b.p, b.p.prepared(), b.st.data()) ==
            Approx(0.5 * b.f.Mbs * b.f.Mbs / (b.p.kn * I)).epsilon(1e-12));
    }
}

TEST_CASE("flatjoint: 3D axial, twist and bending, memo Eq. 64-66", "[flatjoint]")
{
  Driver<3> a(memo_params<3>(2, 8));
  a.move(1e-3, 0, 0, 0, 0, 0);
  CHECK(a.f.Fn == Approx(1.8221e5).epsilon(1e-4));
  CHECK(max_abs({a.f.Fss, a.f.Fst, a.f.Mt, a.f.Mbs, a.f.Mbt}) < 1e-6 * a.f.Fn);
  CHECK(FlatJointLaw<3>::strain_energy(a.p, a.p.prepared(), a.st.data()) ==
        Approx(0.5 * a.f.Fn * a.f.Fn / (a.p.kn * M_PI * 25e-6)).epsilon(1e-12));

  struct Case
  {
    int    Nr, Nal;
    double Mt, Mb;
  };
  for (Case c : {Case{2, 8, -1.8112e2, -4.1657e2}, Case{3, 16, -1.9211e2, -4.4185e2},
                 Case{4, 24, -1.9495e2, -4.4838e2}})
    {
      INFO("{Nr, Nal} = {" << c.Nr << ", " << c.Nal << "}");
      Driver<3> t(memo_params<3>(c.Nr, c.Nal));
      t.move(0, 0, 0, 0.2, 0, 0);
      CHECK(t.f.Mt == Approx(c.Mt).epsilon(1e-4));
      CHECK(max_abs({t.f.Fn, t.f.Fss, t.f.Fst, t.f.Mbs, t.f.Mbt}) <
            1e-6 * std::abs(t.f.Mt));
      Driver<3> b(memo_params<3>(c.Nr, c.Nal));
      b.move(0, 0, 0, 0, 0, 0.4);
      CHECK(b.f.Mbt == Approx(c.Mb).epsilon(1e-4));
      CHECK(max_abs({b.f.Fn, b.f.Fss, b.f.Fst, b.f.Mt, b.f.Mbs}) <
            1e-6 * std::abs(b.f.Mbt));
    }
}

TEST_CASE("flatjoint: 3D twist and bend converge from below", "[flatjoint]")
{
  // memo §2.1.5: converge to the closed forms -1.9806e2 and -4.5553e2 from below
  const double R = 5e-3, kn = 2.32e12, ks = kn / (2 * 1.15);
  const double Mt_exact = -ks * 0.5 * M_PI * std::pow(R, 4) * 0.2;
  const double Mb_exact = -kn * 0.25 * M_PI * std::pow(R, 4) * 0.4;
  CHECK(Mt_exact == Approx(-1.9806e2).epsilon(1e-4));
  CHECK(Mb_exact == Approx(-4.5553e2).epsilon(1e-4));
  double last_t = 0, last_b = 0;
  for (auto [Nr, Nal] : {std::pair{2, 8}, {3, 16}, {4, 24}, {6, 36}, {8, 48}})
    {
      INFO("{Nr, Nal} = {" << Nr << ", " << Nal << "}");
      Driver<3> t(memo_params<3>(Nr, Nal));
      t.move(0, 0, 0, 0.2, 0, 0, 10);
      Driver<3> b(memo_params<3>(Nr, Nal));
      b.move(0, 0, 0, 0, 0, 0.4, 10);
      CHECK(std::abs(t.f.Mt) > std::abs(last_t));
      CHECK(std::abs(b.f.Mbt) > std::abs(last_b));
      CHECK(std::abs(t.f.Mt) < std::abs(Mt_exact));
      CHECK(std::abs(b.f.Mbt) < std::abs(Mb_exact));
      last_t = t.f.Mt, last_b = b.f.Mbt;
    }
  // {8,48} is within 1 % of the closed forms
  CHECK(last_t == Approx(Mt_exact).epsilon(1e-2));
  CHECK(last_b == Approx(Mb_exact).epsilon(1e-2));
}

TEST_CASE("flatjoint: 2D element integrals Eq. 46-49 vs numerical integration",
          "[flatjoint]")
{
  const double kn = 2.32e12, rbar = 1.25e-3;
  struct G
  {
    double ga, gb;
  };
  for (G g : {G{-2e-4, 3e-4}, G{3e-4, -1e-4}, G{1e-4, 2e-4}, G{-1e-4, -3e-4}})
    for (bool bonded : {true, false})
      {
        INFO("ga = " << g.ga << " gb = " << g.gb << " bonded = " << bonded);
        double Fn, Mb;
        FlatJointLaw<2>::integrate_2d(kn, rbar, g.ga, g.gb, bonded, Fn, Mb);
        // 1e5-point midpoint rule of sigma (Eq. 28) with the gap of Eq. 44; the
        // kink at g = 0 costs O(h^2) ~ 1e-10 relative.
        const int    N = 100000;
        const double h = 2 * rbar / N;
        double       F = 0, M = 0;
        for (int i = 0; i < N; ++i)
          {
            const double z   = (i + 0.5) * h;
            const double gap = g.ga + (g.gb - g.ga) / (2 * rbar) * z;
            const double sig = (!bonded && gap >= 0) ? 0.0 : kn * gap;
            F += sig * h;
            M -= (z - rbar) * sig * h;
          }
        const double fscale = kn * rbar * 4e-4, mscale = fscale * rbar;
        if (!bonded && g.ga >= 0 && g.gb >= 0)
          {
            CHECK(Fn == 0);
            CHECK(Mb == 0);
          }
        else
          {
            CHECK(Fn == Approx(F).epsilon(1e-8).margin(1e-12 * fscale));
            CHECK(Mb == Approx(M).epsilon(1e-8).margin(1e-12 * mscale));
          }
      }
}

TEST_CASE("flatjoint: tensile breakage at sigma > sigma_c", "[flatjoint]")
{
  for (int dim3 : {0, 1})
    {
      auto run = [&](auto law_dim) {
        constexpr int dim = decltype(law_dim)::value;
        auto          p   = memo_params<dim>(2, 4);
        p.ten             = 1e9; // gap at break: sigma_c / kn = 4.31e-4 m
        const double gc   = p.ten / p.kn;
        // just below: uniform opening to 0.999 gc in one step
        Driver<dim> a(p);
        a.move(0.999 * gc, 0, 0, 0, 0, 0, 1);
        CHECK(a.count(LawEvent::bond_break) == 0);
        CHECK(FlatJointLaw<dim>::bonded_count(p, a.st.data()) ==
              FlatJointLaw<dim>::element_count(p));
        CHECK(a.f.Fn == Approx(p.kn * 0.999 * gc * (dim == 2 ? 1e-2 : M_PI * 25e-6)));
        // just above: every element breaks once in tension, forces reset
        a.move(0.002 * gc, 0, 0, 0, 0, 0, 1);
        CHECK(a.count(LawEvent::bond_break) == FlatJointLaw<dim>::element_count(p));
        for (auto &ev : a.sink.events)
          {
            CHECK(ev.second.mode == 0);
            CHECK(ev.second.strength == p.ten);
            CHECK(ev.second.gap == Approx(1.001 * gc));
          }
        // first element: 2D length 2R/Nr; 3D inner-ring quarter of area
        // pi (R/2)^2 / 4, so 2 r_e = R/2 (fistPkg §3.4 crack size)
        CHECK(a.sink.events[0].second.size == Approx(dim == 2 ? 5e-3 : 2.5e-3));
        for (int e = 0; e < FlatJointLaw<dim>::element_count(p); ++e)
          {
            CHECK(FlatJointLaw<dim>::bond_state(p, a.st.data(), e) == 1);
            auto fe = FlatJointLaw<dim>::element_force(p, p.prepared(), a.st.data(), e);
            CHECK(fe[0] == 0);
            CHECK(fe[1] == 0);
            CHECK(fe[2] == 0);
          }
        CHECK(a.f.Fn == 0);
        CHECK_FALSE(FlatJointLaw<dim>::active(p, p.prepared(), a.st.data(), 0)); // open, unbonded
        // further steps: no more events (elements stay broken)
        a.move(1e-4, 0, 0, 0, 0, 0, 3);
        CHECK(a.count(LawEvent::bond_break) == FlatJointLaw<dim>::element_count(p));
      };
      if (dim3)
        run(std::integral_constant<int, 3>{});
      else
        run(std::integral_constant<int, 2>{});
    }
}

TEST_CASE("flatjoint: shear breakage at tau > c - sigma tan(phi)", "[flatjoint]")
{
  // 3D {1,3}: compress, then shear along t; tau = ks |d_st| uniform.
  auto p            = memo_params<3>(1, 3);
  p.coh             = 1e8;
  p.fa              = 30;
  p.fric            = 0.5;
  const double gn   = -2e-5; // compression sigma = kn gn = -4.64e7
  const double sig  = p.kn * gn;
  const double tauc = p.coh - sig * std::tan(30 * M_PI / 180);
  const double dc   = tauc / p.ks; // shear displacement at failure
  Driver<3>    a(p);
  a.move(gn, 0, 0, 0, 0, 0, 10);
  a.move(0, 0, 0.999 * dc, 0, 0, 0, 1000);
  CHECK(a.count(LawEvent::bond_break) == 0);
  auto         fe = FlatJointLaw<3>::element_force(p, p.prepared(), a.st.data(), 0);
  const double A  = FlatJointLaw<3>::element_area(p, a.st.data(), 0);
  CHECK(fe[2] / A == Approx(-0.999 * tauc).epsilon(1e-9));
  CHECK(a.f.Fst == Approx(-0.999 * tauc * M_PI * 25e-6).epsilon(1e-9));
  a.move(0, 0, 0.002 * dc, 0, 0, 0, 1);
  REQUIRE(a.count(LawEvent::bond_break) == 3);
  for (auto &ev : a.sink.events)
    {
      CHECK(ev.second.kind == LawEvent::bond_break);
      CHECK(ev.second.mode == 1);
      CHECK(ev.second.strength == Approx(tauc));
    }
  for (int e = 0; e < 3; ++e)
    {
      CHECK(FlatJointLaw<3>::bond_state(p, a.st.data(), e) == 2);
      auto f = FlatJointLaw<3>::element_force(p, p.prepared(), a.st.data(), e);
      CHECK(f[1] == 0);
      CHECK(f[2] == 0);
      // Fn re-evaluated as unbonded: still compressive kn g A
      CHECK(f[0] == Approx(sig * A).epsilon(1e-12));
    }
  CHECK(a.f.Fst == 0);
  // Without the tan(phi) term the same displacement would have broken it:
  // c / ks < 0.999 dc, so the compression term matters here.
  CHECK(p.coh / p.ks < 0.999 * dc);
  // afterwards: frictional with tau_c = -mu sigma; ks * 1e-4 = 1e8 Pa is
  // above mu |sigma| = 2.3e7 Pa, so it slips
  a.move(0, 0, 1e-4, 0, 0, 0, 10);
  CHECK(a.f.Fst == Approx(0.5 * sig * M_PI * 25e-6).epsilon(1e-12));
  CHECK(a.count(LawEvent::bond_break) == 3);
}

TEST_CASE("flatjoint: unbonded Coulomb slip, slip energy Eq. 39, events", "[flatjoint]")
{
  auto p   = memo_params<3>(2, 4);
  p.bonded = false;
  p.fric   = 0.4;
  Driver<3>    a(p);
  const double gn = -1e-5, sig = p.kn * gn, A = M_PI * 25e-6;
  a.move(gn, 0, 0, 0, 0, 0, 10);
  CHECK(a.f.Fn == Approx(sig * A));
  CHECK(a.f.Fss == 0);
  // shear along s: elastic until ks d = mu |sigma|, i.e. d = 4.6e-6
  const double dslip = -0.4 * sig / p.ks;
  const int    n     = 1000;
  const double total = 3 * dslip, inc = total / n;
  a.move(0, total, 0, 0, 0, 0, n);
  CHECK(a.count(LawEvent::slip_start) == 8);
  CHECK(a.count(LawEvent::slip_end) == 0);
  CHECK(a.f.Fss == Approx(0.4 * sig * A).epsilon(1e-12)); // |Fs| = mu |Fn|
  CHECK(std::abs(a.f.Fss) == Approx(p.fric * std::abs(a.f.Fn)).epsilon(1e-12));
  // slipping steps: the first step with ks * i * inc > mu |sigma|
  const int    first = int(std::floor(dslip / inc)) + 1;
  const double Eexp  = (n - first + 1) * (-0.4 * sig) * A * inc; // Eq. 39 summed
  CHECK(FlatJointLaw<3>::slip_energy(p, p.prepared(), a.st.data()) == Approx(Eexp).epsilon(1e-9));
  // reverse: slip ends
  a.move(0, -1e-7, 0, 0, 0, 0, 1);
  CHECK(a.count(LawEvent::slip_end) == 8);
  CHECK(std::abs(a.f.Fss) < std::abs(0.4 * sig * A));
  CHECK(a.sink.events.front().second.kind == LawEvent::slip_start);
  CHECK(a.sink.events.back().second.kind == LawEvent::slip_end);
}

TEST_CASE("flatjoint: alpha of Eq. 33 when an unbonded element closes", "[flatjoint]")
{
  auto p   = memo_params<3>(1, 3);
  p.bonded = false;
  p.fric   = 1e6; // no slip
  p.gap0   = 1e-6;
  Driver<3> a(p);
  CHECK(FlatJointLaw<3>::surface_gap(a.st.data()) == 1e-6);
  CHECK_FALSE(FlatJointLaw<3>::active(p, p.prepared(), a.st.data(), 0));
  // one step: gap 1e-6 -> -3e-6 with shear d_st = 2e-6; alpha = 3/4
  a.move(-4e-6, 0, 2e-6, 0, 0, 0, 1);
  const double A = M_PI * 25e-6;
  CHECK(a.f.Fst == Approx(-p.ks * A * 0.75 * 2e-6).epsilon(1e-12));
  CHECK(a.f.Fn == Approx(p.kn * A * -3e-6).epsilon(1e-12));
  CHECK(FlatJointLaw<3>::active(p, p.prepared(), a.st.data(), 0));
  // next step, already closed: full increment
  a.move(0, 0, 1e-6, 0, 0, 0, 1);
  CHECK(a.f.Fst == Approx(-p.ks * A * 2.5e-6).epsilon(1e-12));
}

TEST_CASE("flatjoint: 2D partial contact, gap0 unbonds, deletion", "[flatjoint]")
{
  // 2D, unbonded: bending opens one side; only the closed part pushes.
  auto p   = memo_params<2>(3, 1);
  p.bonded = false;
  Driver<2> a(p);
  a.move(-1e-4, 0, 0, 0, 0.05, 0); // g(rho) = -1e-4 + 0.05 rho
  // closed for rho < 2e-3: stress kn (g_s + rho theta) on [-R, 2e-3]
  const double R = 5e-3, gs = -1e-4, th = 0.05, r0 = -gs / th;
  const double F = p.kn * (gs * (r0 + R) + th * (r0 * r0 - R * R) / 2);
  const double Mz =
      p.kn * (gs * (r0 * r0 - R * R) / 2 + th * (r0 * r0 * r0 + R * R * R) / 3);
  CHECK(a.f.Fn == Approx(F).epsilon(1e-10));
  CHECK(a.f.Mbs == Approx(-Mz).epsilon(1e-10));

  auto q = memo_params<2>(2, 1);
  q.gap0 = 1e-5; // Table 5: g_o > 0 => unbonded although bonded = true
  Driver<2> b(q);
  CHECK(FlatJointLaw<2>::bonded_count(q, b.st.data()) == 0);
  CHECK(FlatJointLaw<2>::bond(q, b.st.data()) == 0); // gap not zero: no bond
  FlatJointLaw<2>::set_initial_gap(q, b.st.data(), 0);
  CHECK(FlatJointLaw<2>::bond(q, b.st.data(), 1) == 1);
  CHECK(FlatJointLaw<2>::bond_state(q, b.st.data(), 0) == 0);
  CHECK(FlatJointLaw<2>::bond_state(q, b.st.data(), 1) == 3);
  CHECK_FALSE(FlatJointLaw<2>::deletable(q, q.prepared(), b.st.data(), 0));
  FlatJointLaw<2>::unbond(q, b.st.data());
  CHECK(FlatJointLaw<2>::bonded_count(q, b.st.data()) == 0);
  b.move(0, 0, 0.9e-2, 0, 0, 0, 10); // 9 mm shear < 2R = 10 mm
  CHECK_FALSE(FlatJointLaw<2>::deletable(q, q.prepared(), b.st.data(), 0));
  b.move(0, 0, 0.2e-2, 0, 0, 0, 10); // 11 mm > 2R
  CHECK(FlatJointLaw<2>::deletable(q, q.prepared(), b.st.data(), 0));
}

TEST_CASE("flatjoint: parameter validation", "[flatjoint]")
{
  using P3 = FlatJointLaw<3>::Params;
  auto bad = [](auto mutate, const char *what) {
    P3 p = memo_params<3>(2, 8);
    mutate(p);
    try
      {
        p.validate("material granite");
        FAIL("no InputError for " << what);
      }
    catch (const InputError &e)
      {
        const std::string m = e.what();
        INFO(m);
        CHECK(m.find(std::string("'") + what + "'") != std::string::npos);
        CHECK(m.find("material granite") != std::string::npos);
      }
  };
  bad([](P3 &p) { p.Nr = 0; }, "Nr");
  bad([](P3 &p) { p.Nal = 2; }, "Nal");
  bad([](P3 &p) { p.rmul = 0; }, "rmul");
  bad([](P3 &p) { p.gap0 = -1e-6; }, "gap0");
  bad([](P3 &p) { p.kn = -1; }, "kn");
  bad([](P3 &p) { p.ks = -1; }, "ks");
  bad([](P3 &p) { p.fric = -0.1; }, "fric");
  bad([](P3 &p) { p.ten = -1; }, "ten");
  bad([](P3 &p) { p.coh = -1; }, "coh");
  bad([](P3 &p) { p.fa = 90; }, "fa");
  bad([](P3 &p) { p.fa = -1; }, "fa");
  bad([](P3 &p) { p.kn = NAN; }, "kn");
  try
    {
      P3 p = memo_params<3>(2, 8);
      p.fa = 90;
      p.validate("x");
    }
  catch (const InputError &e)
    {
      CHECK(std::string(e.what()).find("[0, 90)") != std::string::npos);
    }
  // 2D ignores Nal (N_alpha = 1)
  auto p2 = memo_params<2>(4, 1);
  CHECK_NOTHROW(p2.validate("2d"));
  CHECK_THROWS_AS(FlatJointLaw<3>::deformability(-1, 1, geometry<3>()), InputError);
}

TEST_CASE("flatjoint: 2D bending breaks only the outer element", "[flatjoint]")
{
  // Nr = 4, R = 5 mm: centroids rho = 3.75, 1.25, -1.25, -3.75 mm. Under
  // theta_bs the element stress is sigma = kn rho theta_bs (Eq. 46, bonded).
  auto         p  = memo_params<2>(4, 1);
  const double th = 1e-3;
  p.ten           = p.kn * 2.5e-3 * th; // between the two tensile elements
  Driver<2> a(p);
  a.move(0, 0, 0, 0, th, 0, 1);
  REQUIRE(a.count(LawEvent::bond_break) == 1);
  const LawEvent ev = a.sink.events[0].second;
  CHECK(ev.element == 0);
  CHECK(ev.mode == 0);
  CHECK(ev.r_s == 0);
  CHECK(ev.r_t == Approx(3.75e-3));
  CHECK(ev.gap == Approx(3.75e-3 * th));
  CHECK(ev.size == Approx(2.5e-3));
  CHECK(FlatJointLaw<2>::bond_state(p, a.st.data(), 0) == 1);
  CHECK(FlatJointLaw<2>::bonded_count(p, a.st.data()) == 3);
  // broken element open over its whole length: no force, no moment
  auto f0 = FlatJointLaw<2>::element_force(p, p.prepared(), a.st.data(), 0);
  CHECK(f0[0] == 0);
  CHECK(f0[3] == 0);
  // resultant of the three bonded elements: linear stress on [-R, 2.5 mm]
  const double R = 5e-3, r1 = 2.5e-3;
  const double Fn = p.kn * th * (r1 * r1 - R * R) / 2;
  const double Mz = p.kn * th * (r1 * r1 * r1 + R * R * R) / 3;
  CHECK(a.f.Fn == Approx(Fn).epsilon(1e-12));
  CHECK(a.f.Mbs == Approx(-Mz).epsilon(1e-12));
  // 2D shear (d_st): bonded elements carry ks A d, the broken open one none
  a.move(0, 0, 1e-6, 0, 0, 0, 1);
  CHECK(a.f.Fst == Approx(-p.ks * 3 * 2.5e-3 * 1e-6).epsilon(1e-12));
  CHECK(a.f.Fss == 0);
  CHECK(a.f.Mt == 0);
  CHECK(a.f.Mbt == 0);
  CHECK(FlatJointLaw<2>::active(p, p.prepared(), a.st.data(), 0));
}
