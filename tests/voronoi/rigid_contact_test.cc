// Rigid Voronoi contact (dem/voronoi/rigid_contact.h; seed 004 §2.3, §2.5):
// geometry from the tessellation of two disks, two-grain normal, shear and
// bending load against the closed forms of the three-point contact, large
// rigid rotation, per-point strengths, and the one-point, zero-offset
// reduction to the point-contact (linear) law of dem/laws/linear_law.h.
//
// Closed forms (small displacements, edge of length L, thickness t, area
// A = L t, points at s = -L/2, 0, L/2 with areas A/6, 2A/3, A/6, point
// stiffnesses kn A_i and ks A_i):
//  - normal approach delta: every point closes by delta, F = kn delta
//    (A/6 + 2A/3 + A/6) = kn A delta;
//  - shear: both grains turning by theta about their centres moves B
//    relative to A by -theta d along t at every point (the relative
//    velocity omega k x (x_A - x_B) is the same everywhere), F_s = ks A d
//    theta; the moment of the point forces about B's centre is -a_B F_s and
//    about A's centre -a_A F_s (a_A, a_B: distances of the edge from the
//    centres along n);
//  - bending: B turning by theta about the reference point x_r closes point
//    i by theta s_i (u_n,i = -theta s_i), F_n,i = -kn A_i theta s_i; the
//    resultant is zero (sum A_i s_i = 0) and the moment about +z on B is
//    sum s_i F_n,i = -kn theta sum A_i s_i^2 = -kn theta I with
//    I = 2 (A/6)(L/2)^2 = A L^2 / 12 = t L^3 / 12: the Lobatto (Simpson)
//    weights integrate s^2 exactly, so the three-point contact has the
//    bending stiffness of the continuous edge.
#include "dem/engine/types.h"
#include "dem/laws/linear_law.h"
#include "dem/voronoi/rigid_contact.h"
#include "dem/voronoi/tessellation.h"
#include "voronoi_test_helpers.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;

namespace
{
  struct Grains
  {
    std::vector<double> x, y, r, vx, vy, om, fx, fy, mz;
    Grains(std::vector<double> x_, std::vector<double> y_, std::vector<double> r_)
        : x(x_)
        , y(y_)
        , r(r_)
        , vx(x.size(), 0)
        , vy(x.size(), 0)
        , om(x.size(), 0)
        , fx(x.size(), 0)
        , fy(x.size(), 0)
        , mz(x.size(), 0)
    {
    }
    GrainKinematics kin() const
    {
      return {x.data(), y.data(), r.data(), vx.data(), vy.data(), om.data()};
    }
    GrainForces forces() { return {fx.data(), fy.data(), mz.data()}; }
    void        step(RigidVoronoiContacts &c, double dt)
    {
      std::fill(fx.begin(), fx.end(), 0.0);
      std::fill(fy.begin(), fy.end(), 0.0);
      std::fill(mz.begin(), mz.end(), 0.0);
      c.update(kin(), dt, forces());
    }
  };

  /// Strong elastic contact (strengths far above the loads of the tests).
  ContactMaterial elastic() { return testing::elastic_lattice_contacts(); }

  // Two disks, R_A = 1 mm at the origin, R_B = 1.5 mm at (d, 0) with a gap.
  constexpr double RA = 1e-3, RB = 1.5e-3, d = 2.6e-3;
  /// Power-bisector position along n from A: (d^2 + R_A^2 - R_B^2) / (2 d).
  constexpr double edge_x = (d * d + RA * RA - RB * RB) / (2 * d);

  RigidVoronoiContacts two_grain_contact(const ContactMaterial &m, double ylo, double yhi,
                                         PointScheme scheme = PointScheme::lobatto3)
  {
    const std::vector<double> x = {0, d}, y = {0, 0}, r = {RA, RB};
    const auto                t =
        laguerre_tessellation(x, y, r, ClipDomain::rectangle(-2e-3, ylo, 5e-3, yhi));
    RigidVoronoiContacts c(m);
    c.add_from_tessellation(t, x, y, r, scheme);
    return c;
  }
} // namespace

TEST_CASE("Rigid Voronoi contact: geometry from the tessellation", "[voronoi][rigid]")
{
  const auto m = elastic();
  const auto c = two_grain_contact(m, -1e-3, 2e-3);
  REQUIRE(c.n_contacts() == 1);
  REQUIRE(c.n_points() == 3);
  CHECK(c.grain_a[0] == 0);
  CHECK(c.grain_b[0] == 1);
  // Offset of the Laguerre edge from the PCM plane:
  // edge_x - (R_A - U/2) = (R_A - R_B)(R_A + R_B - d) / (2 d) = 9.6e-6 m.
  // Both sides are differences of mm-sized numbers: their roundoff is
  // ~1e-19 m, so 1e-16 m (1e-11 relative) is a safe bound.
  CHECK(std::abs(c.offset[0] - (RA - RB) * (RA + RB - d) / (2 * d)) <= 1e-16);
  CHECK(c.edge_length[0] == Approx(3e-3).epsilon(1e-12));
  const double A = 3e-3 * m.thickness;
  // t = k x n = +y, the reference point is on the centre line: s = y.
  const double s_lo = std::min(c.s[0], c.s[2]), s_hi = std::max(c.s[0], c.s[2]);
  CHECK(s_lo == Approx(-1e-3).epsilon(1e-12));
  CHECK(s_hi == Approx(2e-3).epsilon(1e-12));
  CHECK(c.s[1] == Approx(0.5e-3).epsilon(1e-12));
  CHECK(c.area[0] == Approx(A / 6).epsilon(1e-12));
  CHECK(c.area[1] == Approx(2 * A / 3).epsilon(1e-12));
  CHECK(c.area[2] == Approx(A / 6).epsilon(1e-12));
  Grains g({0, d}, {0, 0}, {RA, RB});
  double xr, yr, nx, ny;
  c.reference_frame(0, g.kin(), xr, yr, nx, ny);
  CHECK(std::abs(xr - edge_x) <= 1e-18);
  CHECK(yr == 0);
  CHECK(nx == 1);
  CHECK(ny == 0);
}

TEST_CASE("Rigid Voronoi contact: normal, shear and bending closed forms",
          "[voronoi][rigid]")
{
  const auto   m = elastic();
  const double L = 2e-3, A = L * m.thickness, ks = m.kn / m.kratio;
  const double I  = m.thickness * L * L * L / 12;
  const double aA = edge_x, aB = d - edge_x;
  const int    N = 10;
  // Positions are held: these are the small-displacement closed forms, and
  // the model then only sums increments, so they hold to roundoff (1e-12).
  auto   c = two_grain_contact(m, -1e-3, 1e-3);
  Grains g({0, d}, {0, 0}, {RA, RB});

  SECTION("normal")
  {
    const double delta = 1e-8;
    g.vx[1]            = -delta / N;
    for (int i = 0; i < N; ++i)
      g.step(c, 1.0);
    const double F = m.kn * A * delta;
    CHECK(g.fx[1] == Approx(F).epsilon(1e-12));
    CHECK(std::abs(g.fy[1]) <= 1e-12 * F);
    CHECK(g.fx[0] == -g.fx[1]);
    CHECK(std::abs(g.mz[0]) <= 1e-12 * F * L);
    CHECK(std::abs(g.mz[1]) <= 1e-12 * F * L);
    for (int p = 0; p < 3; ++p)
      CHECK(c.fn[p] == Approx(-m.kn * c.area[p] * delta).epsilon(1e-12));
  }
  SECTION("shear")
  {
    const double theta = 1e-6;
    g.om[0] = g.om[1] = theta / N;
    for (int i = 0; i < N; ++i)
      g.step(c, 1.0);
    const double Fs = ks * A * d * theta;
    CHECK(g.fy[1] == Approx(Fs).epsilon(1e-12));
    CHECK(std::abs(g.fx[1]) <= 1e-12 * Fs);
    CHECK(g.mz[1] == Approx(-aB * Fs).epsilon(1e-12));
    CHECK(g.mz[0] == Approx(-aA * Fs).epsilon(1e-12));
    // Equilibrium of the pair about the origin: M_A + M_B + d F_y,B = 0.
    CHECK(std::abs(g.mz[0] + g.mz[1] + d * g.fy[1]) <= 1e-12 * Fs * d);
  }
  SECTION("bending about the reference point")
  {
    const double theta = 1e-6;
    g.om[1]            = theta / N;
    g.vy[1]            = aB * theta / N; // B's velocity is zero at x_r
    for (int i = 0; i < N; ++i)
      g.step(c, 1.0);
    const double M = m.kn * I * theta;
    CHECK(g.mz[1] == Approx(-M).epsilon(1e-12));
    CHECK(g.mz[0] == Approx(M).epsilon(1e-12));
    // Zero resultant: relative to kn A theta L, the scale of a point force.
    CHECK(std::abs(g.fx[1]) <= 1e-12 * m.kn * A * theta * L);
    CHECK(std::abs(g.fy[1]) <= 1e-12 * m.kn * A * theta * L);
  }
}

TEST_CASE("Rigid Voronoi contact: bending of an edge off the centre line",
          "[voronoi][rigid]")
{
  // Edge from y = -1 mm to 2 mm: L = 3 mm, midpoint at s = 0.5 mm. Turning
  // B about the midpoint gives zero resultant and the moment -kn I theta
  // with I = t L^3 / 12 about any point.
  const auto   m = elastic();
  const double L = 3e-3, I = m.thickness * L * L * L / 12, A = L * m.thickness;
  auto         c = two_grain_contact(m, -1e-3, 2e-3);
  Grains       g({0, d}, {0, 0}, {RA, RB});
  const double theta = 1e-6, mid_y = 0.5e-3;
  const int    N = 10;
  g.om[1]        = theta / N;
  // v_B = -omega k x (x_m - x_B), x_m - x_B = (edge_x - d, mid_y).
  g.vx[1] = theta / N * mid_y;
  g.vy[1] = -theta / N * (edge_x - d);
  for (int i = 0; i < N; ++i)
    g.step(c, 1.0);
  CHECK(g.mz[1] == Approx(-m.kn * I * theta).epsilon(1e-12));
  CHECK(std::abs(g.fx[1]) <= 1e-12 * m.kn * A * theta * L);
  CHECK(std::abs(g.fy[1]) <= 1e-12 * m.kn * A * theta * L);
}

TEST_CASE(
    "Rigid Voronoi contact: a rigid rotation of the pair leaves the force unchanged",
    "[voronoi][rigid]")
{
  const auto   m = elastic();
  const double L = 2e-3, A = L * m.thickness;
  auto         c = two_grain_contact(m, -1e-3, 1e-3);
  Grains       g({0, d}, {0, 0}, {RA, RB});
  const double delta = 1e-7;
  g.vx[1]            = -delta;
  g.step(c, 1.0);
  g.vx[1] = 0;
  // Turn the pair by 90 degrees about the origin in M steps; positions are
  // rotated exactly, velocities are the rigid field omega k x x.
  const int    M     = 2000;
  const double omega = 0.5 * M_PI / M;
  for (int i = 0; i < M; ++i)
    {
      for (int k = 0; k < 2; ++k)
        {
          g.om[k] = omega;
          g.vx[k] = -omega * g.y[k];
          g.vy[k] = omega * g.x[k];
        }
      g.step(c, 1.0);
      const double cs = std::cos(omega), sn = std::sin(omega);
      for (int k = 0; k < 2; ++k)
        {
          const double x = g.x[k], y = g.y[k];
          g.x[k] = cs * x - sn * y;
          g.y[k] = sn * x + cs * y;
        }
    }
  g.om = {0, 0};
  g.vx = {0, 0};
  g.vy = {0, 0};
  g.step(c, 1.0);
  // Now n = +y. Roundoff of the relative velocity (eps |omega x|) summed
  // over M steps is ~1e-19 m against delta = 1e-7 m: 1e-10 is safe.
  const double F = m.kn * A * delta;
  CHECK(g.fy[1] == Approx(F).epsilon(1e-10));
  CHECK(std::abs(g.fx[1]) <= 1e-10 * F);
  CHECK(std::abs(g.mz[1]) <= 1e-10 * F * L);
}

TEST_CASE("Rigid Voronoi contact: per-point tensile strength under tension and bending",
          "[voronoi][rigid]")
{
  auto m             = elastic();
  m.tensile_strength = 5e6;
  m                  = m.brittle();
  const double L = 2e-3, A = L * m.thickness;
  Grains       g({0, d}, {0, 0}, {RA, RB});

  SECTION("uniform tension: all points break at sigma_t A together")
  {
    auto         c  = two_grain_contact(m, -1e-3, 1e-3);
    const double du = m.tensile_strength / m.kn / 137.3;
    g.vx[1]         = du;
    double last     = 0;
    int    i        = 0;
    for (; i < 1000 && g.fx[1] <= 0; ++i)
      {
        last = -g.fx[1];
        g.step(c, 1.0);
        if (g.fx[1] == 0 && i > 0)
          break;
      }
    // Last force before the break: 137 elastic steps of kn A du.
    CHECK(last == Approx(137 * m.kn * A * du).epsilon(1e-12));
    CHECK(last <= m.tensile_strength * A);
    CHECK(g.fx[1] == 0);
    for (int p = 0; p < 3; ++p)
      CHECK(c.crack[p] == PointCrack::tensile);
  }
  SECTION("bending: the end in tension breaks first, at kn theta L/2 = sigma_t")
  {
    auto         c       = two_grain_contact(m, -1e-3, 1e-3);
    const double aB      = d - edge_x;
    const double theta_c = 2 * m.tensile_strength / (m.kn * L);
    const double dtheta  = theta_c / 100.5;
    g.om[1]              = dtheta;
    g.vy[1]              = aB * dtheta;
    for (int i = 0; i < 100; ++i)
      g.step(c, 1.0);
    for (int p = 0; p < 3; ++p)
      CHECK(c.crack[p] == PointCrack::intact);
    g.step(c, 1.0);
    // u_n = -theta s opens the point with s < 0.
    const int lo = c.s[0] < 0 ? 0 : 2, hi = 2 - lo;
    CHECK(c.crack[lo] == PointCrack::tensile);
    CHECK(c.crack[1] == PointCrack::intact);
    CHECK(c.crack[hi] == PointCrack::intact);
  }
}

TEST_CASE("Rigid Voronoi contact: one point at the reference point is the point contact",
          "[voronoi][rigid]")
{
  // Equal radii: the Laguerre edge is the PCM plane (delta = 0). With one
  // point of area A at x_r, no strength (a frictional contact) and
  // kn A, ks A as the point stiffnesses, the model must reproduce the
  // linear law (dem/laws/linear_law.h) applied at the PCM contact point.
  auto m                      = elastic();
  m.tensile_strength          = 0;
  m.cohesion                  = 0;
  m                           = m.brittle();
  const double              R = 1e-3, L = 2e-3, A = L * m.thickness;
  const std::vector<double> x = {0, 2 * R}, y = {0, 0}, r = {R, R};
  const auto t = laguerre_tessellation(x, y, r, ClipDomain::rectangle(-R, -R, 3 * R, R));
  RigidVoronoiContacts c(m);
  c.add_from_tessellation(t, x, y, r, PointScheme::reference_point);
  REQUIRE(c.n_points() == 1);
  CHECK(std::abs(c.offset[0]) <= 1e-18);
  CHECK(c.area[0] == Approx(A).epsilon(1e-12));

  // The reference point is the PCM point x_A + (R_A - U/2) n in any
  // configuration (gapped, overlapping, turned).
  {
    Grains g({0.1e-3, 1.9e-3}, {0.2e-3, 1.1e-3}, {R, R});
    for (double shift : {-0.3e-3, 0.0, 0.4e-3})
      {
        g.x[1] = 1.9e-3 + shift;
        double xr, yr, nx, ny;
        c.reference_frame(0, g.kin(), xr, yr, nx, ny);
        const double dx = g.x[1] - g.x[0], dy = g.y[1] - g.y[0], dd = std::hypot(dx, dy);
        const double U = 2 * R - dd;
        CHECK(std::abs(xr - (g.x[0] + (R - U / 2) * dx / dd)) <= 1e-18);
        CHECK(std::abs(yr - (g.y[0] + (R - U / 2) * dy / dd)) <= 1e-18);
      }
  }

  LinearLaw<2>::Params lin;
  lin.kn                 = m.kn * A;
  lin.ks                 = m.kn / m.kratio * A;
  lin.friction           = m.friction;
  lin.reference_gap      = 0;
  const auto          lp = lin.prepared();
  std::vector<double> st(LinearLaw<2>::state_size(lp));
  ContactStep<2>      k;
  k.n  = Vec<2>(1, 0);
  k.t  = Vec<2>(0, 1);
  k.xc = Vec<2>(R, 0);
  k.R1 = k.R2 = R;
  LinearLaw<2>::install(lp, lp, k, st.data());
  EventSink events;

  Grains                                 g(x, y, r);
  std::mt19937                           gen(3u);
  std::uniform_real_distribution<double> u(-1, 1);
  double                                 gap = 0, fscale = 0;
  int                                    n_slip = 0, n_open = 0;
  for (int i = 0; i < 400; ++i)
    {
      // Phases: compress, shear and turn (slip), open, close again.
      const double vn = i < 100 ? -1e-9 : i < 200 ? 0.0 : i < 300 ? 1.5e-9 : -1.5e-9;
      g.vx            = {0.0, vn};
      g.vy            = {1e-9 * u(gen), 3e-9 * u(gen)};
      g.om            = {2e-6 * u(gen), 2e-6 * u(gen)};
      // Point-contact kinematics at x_c (memo Eq. 2-11): relative velocity
      // of B with respect to A at x_c.
      const double vrx = (g.vx[1] - g.om[1] * 0) - (g.vx[0] - g.om[0] * 0);
      const double vry = (g.vy[1] + g.om[1] * (R - 2 * R)) - (g.vy[0] + g.om[0] * R);
      k.d_n            = vrx;
      k.d_st           = vry;
      gap += k.d_n;
      k.gap = gap;
      ContactForce f;
      LinearLaw<2>::update(lp, lp, k, st.data(), f, events);
      g.step(c, 1.0);
      // Linear law: force -Fn n + Fst t on B at x_c.
      const double Fx = -f.Fn, Fy = f.Fst;
      const double MB = (R - 2 * R) * Fy, MA = -(R * Fy);
      fscale           = std::max(fscale, std::hypot(Fx, Fy));
      const double tol = 1e-12 * fscale; // same arithmetic up to roundoff
      CHECK(std::abs(g.fx[1] - Fx) <= tol);
      CHECK(std::abs(g.fy[1] - Fy) <= tol);
      CHECK(std::abs(g.mz[1] - MB) <= tol * R);
      CHECK(std::abs(g.mz[0] - MA) <= tol * R);
      n_slip += f.Fn < 0 && std::abs(std::abs(f.Fst) + m.friction * f.Fn) <= tol;
      n_open += gap > 0;
    }
  // The history exercised slip and separation, not only the elastic range.
  CHECK(n_slip > 10);
  CHECK(n_open > 10);
}
