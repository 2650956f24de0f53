// Bilinear-softening point law (dem/voronoi/softening_law.h; seed 004 §2.6,
// Fig. 3): the curve in tension and shear against its closed form, the
// dissipated energy to full separation against G A, unloading and crack
// closure, the coupling of the damages, and the brittle limit against the
// brittle tension cut-off / Mohr-Coulomb law.
#include "dem/engine/types.h"
#include "dem/voronoi/softening_law.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;

namespace
{
  /// Rock-like contact: kn = 1e13 Pa/m, sigma_t = 5 MPa, c = 20 MPa.
  /// Elastic energies at the peaks: 1.25 J/m^2 (tension), 2 * 20 = 40 J/m^2
  /// (shear, ks = kn / 2).
  ContactMaterial rock()
  {
    ContactMaterial m;
    m.kn                      = 1e13;
    m.kratio                  = 2;
    m.tensile_strength        = 5e6;
    m.cohesion                = 20e6;
    m.friction                = 0.6;
    m.tensile_fracture_energy = 20;
    m.shear_fracture_energy   = 200;
    m.thickness               = 1;
    return m;
  }

  /// One local point driven by prescribed displacement increments.
  struct Point
  {
    SofteningCoefficients k;
    double                A  = 1e-3;
    double                un = 0, wn = 0, fs = 0, dt = 0, ds = 0;
    PointCrack            crack;
    double                fn = 0;
    explicit Point(const ContactMaterial &m)
        : k(SofteningCoefficients::derive(m))
        , crack(k.initial_crack())
    {
    }
    void step(double d_un, double d_us)
    {
      fn = update_point(k, A, d_un, d_us, PointState{un, wn, fs, dt, ds, crack});
    }
  };
} // namespace

TEST_CASE("Softening law, tension: bilinear curve and G_t A to full separation",
          "[voronoi][softening]")
{
  const auto   m = rock();
  Point        p(m);
  const double u0   = m.tensile_strength / m.kn;                          // peak opening
  const double uc   = 2 * m.tensile_fracture_energy / m.tensile_strength; // zero stress
  const int    N    = 20000;
  const double du   = 1.25 * uc / N;
  double       work = 0, fmax = 0;
  for (int i = 0; i < N; ++i)
    {
      const double f_old = p.fn;
      p.step(du, 0);
      // Work done on the point by the opening: the force pulls back (tension
      // positive), the trapezoid rule is exact on each linear piece.
      work += 0.5 * (f_old + p.fn) * du;
      fmax = std::max(fmax, p.fn);
      // Closed form of Fig. 3a: kn A u up to the peak, then the line to zero
      // at uc; 1e-9 of the peak force covers roundoff of the accumulated u.
      const double u = p.un;
      const double expected =
          u <= u0 ? m.kn * p.A * u
                  : std::max(0.0, m.tensile_strength * p.A * (uc - u) / (uc - u0));
      CHECK(std::abs(p.fn - expected) <= 1e-9 * m.tensile_strength * p.A);
      CHECK(p.dt + p.ds <= 1 + 1e-15);
    }
  CHECK(p.crack == PointCrack::tensile);
  CHECK(p.fn == 0);
  CHECK(fmax <= m.tensile_strength * p.A * (1 + 1e-12));
  // Energy: 1 % is asked for; the return mapping is exact, so the only
  // error is the trapezoid rule over a step holding the peak kink or the
  // break, of order du / uc = 6e-5 of G A at most (here both fall on step
  // boundaries and the measured error is ~1e-13).
  CHECK(work == Approx(m.tensile_fracture_energy * p.A).epsilon(1e-4));
}

TEST_CASE(
    "Softening law, tension: unloading is elastic, closure is free, energy unchanged",
    "[voronoi][softening]")
{
  const auto   m = rock();
  Point        p(m);
  const double uc    = 2 * m.tensile_fracture_energy / m.tensile_strength;
  const int    N     = 4000;
  double       work  = 0;
  auto         drive = [&](double target) {
    const double du = (target - p.un) / N;
    for (int i = 0; i < N; ++i)
      {
        const double f_old = p.fn;
        p.step(du, 0);
        work += 0.5 * (f_old + p.fn) * du;
      }
  };
  drive(0.3 * uc); // onto the softening branch
  const double f1 = p.fn, u1 = p.un;
  REQUIRE(f1 > 0);
  REQUIRE(p.dt > 0);
  // Unloading with slope kn A: residual opening u1 - f1 / (kn A).
  const double du_back = -0.1 * f1 / (m.kn * p.A);
  p.step(du_back, 0);
  work += 0.5 * (f1 + p.fn) * du_back;
  CHECK(p.fn == Approx(0.9 * f1).epsilon(1e-12));
  drive(-1e-7); // close the crack and compress
  // Faces meet at the installed position: compression kn A u.
  CHECK(p.fn == Approx(-m.kn * p.A * 1e-7).epsilon(1e-9));
  // Damage kept through unloading and closure: D_t = w_n / uc with the
  // inelastic opening w_n = u1 - f1 / (kn A) reached on the branch.
  CHECK(p.dt == Approx((u1 - f1 / (m.kn * p.A)) / uc).epsilon(1e-9));
  drive(0.6 * uc);
  drive(0.0);
  drive(1.2 * uc);
  CHECK(p.crack == PointCrack::tensile);
  CHECK(p.un > u1);
  // Unloading, closure and reloading are elastic or free: the dissipation
  // is still G_t A (same 1e-4 as the monotonic test).
  CHECK(work == Approx(m.tensile_fracture_energy * p.A).epsilon(1e-4));
}

TEST_CASE("Softening law, shear: G_s A without and with compression",
          "[voronoi][softening]")
{
  const auto   m   = rock();
  const double ks  = m.kn / m.kratio;
  const double us0 = m.cohesion / ks;
  const double usc = 2 * m.shear_fracture_energy / m.cohesion;
  const int    N   = 20000;

  SECTION("zero normal force")
  {
    Point  p(m);
    double work = 0;
    for (int i = 0; i < N; ++i)
      {
        const double du = 1.25 * usc / N, f_old = p.fs;
        p.step(0, du);
        // Shear force on B opposes its displacement: work = -int fs du.
        work -= 0.5 * (f_old + p.fs) * du;
        const double u = i + 1 == N ? 1.25 * usc : (i + 1) * du;
        const double expected =
            u <= us0 ? ks * p.A * u
                     : std::max(0.0, m.cohesion * p.A * (usc - u) / (usc - us0));
        CHECK(std::abs(-p.fs - expected) <= 1e-9 * m.cohesion * p.A);
      }
    CHECK(p.crack == PointCrack::shear);
    CHECK(p.fs == 0);
    CHECK(p.fn == 0);
    // du / usc = 6e-5: as in tension.
    CHECK(work == Approx(m.shear_fracture_energy * p.A).epsilon(1e-4));
  }
  SECTION("under compression the cohesion softens, the friction stays")
  {
    Point        p(m);
    const double sigma = 10e6, uc = sigma / m.kn;
    p.step(-uc, 0);
    const double N_force = sigma * p.A;
    REQUIRE(p.fn == Approx(-N_force).epsilon(1e-12));
    double       work  = 0;
    const double total = 1.5 * usc, du = total / N;
    for (int i = 0; i < N; ++i)
      {
        const double f_old = p.fs;
        p.step(0, du);
        work -= 0.5 * (f_old + p.fs) * du;
      }
    CHECK(p.crack == PointCrack::shear);
    const double residual = m.friction * N_force;
    CHECK(-p.fs == Approx(residual).epsilon(1e-12));
    // External work = cohesive fracture energy + friction on the slip
    // + elastic energy left in the shear spring.
    const double slip = total - residual / (ks * p.A);
    CHECK(work == Approx(m.shear_fracture_energy * p.A + residual * slip +
                         0.5 * residual * residual / (ks * p.A))
                      .epsilon(1e-4));
    CHECK(p.fn == Approx(-N_force).epsilon(1e-12));
  }
}

TEST_CASE("Softening law, shear under tension: lower peak, tensile crack, no friction",
          "[voronoi][softening]")
{
  const auto   m  = rock();
  const double ks = m.kn / m.kratio;
  Point        p(m);
  // Tension at half the tensile strength, held.
  p.step(0.5 * m.tensile_strength / m.kn, 0);
  const double fn0 = 0.5 * m.tensile_strength * p.A;
  REQUIRE(p.fn == Approx(fn0).epsilon(1e-12));
  // Mohr-Coulomb in tension: c A - mu F_n.
  const double peak = m.cohesion * p.A - m.friction * fn0;
  const double du   = peak / (ks * p.A) / 500.3;
  double       fmax = 0;
  for (int i = 0; i < 100000 && p.crack == PointCrack::intact; ++i)
    {
      p.step(0, du);
      fmax = std::max(fmax, -p.fs);
      CHECK(-p.fs >= 0); // never reverses under monotonic slip
    }
  // The last elastic step is within one increment ks A du of the peak.
  CHECK(fmax <= peak * (1 + 1e-12));
  CHECK(fmax >= peak - ks * p.A * du * (1 + 1e-9));
  // Broken under tension: a tensile crack (seed 004 §2.6), no friction.
  CHECK(p.crack == PointCrack::tensile);
  p.step(0, du);
  CHECK(p.fs == 0);
  CHECK(p.fn == 0);
}

TEST_CASE("Softening law: the damages add and reduce both strengths",
          "[voronoi][softening]")
{
  const auto   m = rock();
  Point        p(m);
  const double ks  = m.kn / m.kratio;
  const double us0 = m.cohesion / ks;
  const double usc = 2 * m.shear_fracture_energy / m.cohesion;
  // Shear onto the softening branch to D_s = 0.4: slip w = 0.4 usc, total
  // displacement w + (1 - 0.4) c / ks.
  const double target = 0.4 * usc + 0.6 * us0;
  const int    N      = 1000;
  for (int i = 0; i < N; ++i)
    p.step(0, target / N);
  CHECK(p.ds == Approx(0.4).epsilon(1e-9));
  CHECK(-p.fs == Approx(0.6 * m.cohesion * p.A).epsilon(1e-9));
  // Tension now peaks at (1 - 0.4) sigma_t (the shear force is held, and
  // with the tension the Mohr-Coulomb limit drops below it, so shear damage
  // grows too: only the first elastic steps are checked against the peak).
  const double u_peak = 0.6 * m.tensile_strength / m.kn;
  double       fmax   = 0;
  for (int i = 0; i < 2000; ++i)
    {
      p.step(1.2 * u_peak / 2000, 0);
      fmax = std::max(fmax, p.fn);
    }
  CHECK(fmax <= 0.6 * m.tensile_strength * p.A * (1 + 1e-12));
  CHECK(p.dt + p.ds > 0.4);
}

TEST_CASE("Softening law, brittle limit: tension cut-off and Mohr-Coulomb",
          "[voronoi][softening]")
{
  const auto   m  = rock().brittle();
  const double ks = m.kn / m.kratio;
  SECTION("tension cut-off")
  {
    Point        p(m);
    const double du    = m.tensile_strength / m.kn / 137.3; // no step lands on the peak
    bool         broke = false;
    for (int i = 0; i < 300; ++i)
      {
        p.step(du, 0);
        // Brittle law: kn A u while below sigma_t A, zero from the first
        // step beyond it on. 1e-12 relative: roundoff of the sum of u.
        const double f = m.kn * p.A * p.un;
        broke          = broke || f > m.tensile_strength * p.A;
        CHECK(p.fn == Approx(broke ? 0.0 : f).epsilon(1e-12).margin(0));
      }
    CHECK(broke);
    CHECK(p.crack == PointCrack::tensile);
    // Brittle failure dissipates exactly the elastic energy at the peak,
    // which is G_t here.
    CHECK(p.dt == 1);
  }
  SECTION("Mohr-Coulomb with residual friction")
  {
    Point        p(m);
    const double sigma = 8e6;
    p.step(-sigma / m.kn, 0);
    const double peak  = (m.cohesion + m.friction * sigma) * p.A;
    const double du    = peak / (ks * p.A) / 211.7;
    bool         broke = false;
    for (int i = 0; i < 400; ++i)
      {
        p.step(0, du);
        const double f        = ks * p.A * (i + 1) * du;
        broke                 = broke || f > peak;
        const double expected = broke ? m.friction * sigma * p.A : f;
        CHECK(-p.fs == Approx(expected).epsilon(1e-12));
      }
    CHECK(p.crack == PointCrack::shear);
  }
}

TEST_CASE(
    "Softening law: no strength is a linear no-tension Coulomb contact, and input checks",
    "[voronoi][softening]")
{
  auto m                    = rock();
  m.tensile_strength        = 0;
  m.cohesion                = 0;
  m.tensile_fracture_energy = 0;
  m.shear_fracture_energy   = 0;
  Point p(m);
  CHECK(p.crack == PointCrack::unbonded);
  p.step(1e-6, 0);
  CHECK(p.fn == 0);
  p.step(-2e-6, 0); // faces meet at u = 0: 1e-6 of compression
  CHECK(p.fn == Approx(-m.kn * p.A * 1e-6).epsilon(1e-9));
  p.step(0, 1.0);
  CHECK(-p.fs == Approx(m.friction * m.kn * p.A * 1e-6).epsilon(1e-9));

  // Fracture energies below the elastic energy at the peak (snap-back).
  auto bad                    = rock();
  bad.tensile_fracture_energy = 0.5 * bad.tensile_elastic_energy();
  CHECK_THROWS_AS(SofteningCoefficients::derive(bad), InputError);
  bad                       = rock();
  bad.shear_fracture_energy = 0.99 * bad.shear_elastic_energy();
  CHECK_THROWS_AS(SofteningCoefficients::derive(bad), InputError);
  bad    = rock();
  bad.kn = 0;
  CHECK_THROWS_AS(SofteningCoefficients::derive(bad), InputError);
  CHECK_NOTHROW(SofteningCoefficients::derive(rock().brittle()));
}
