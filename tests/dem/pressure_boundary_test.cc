// The pressure boundary of 2D compression specimens (dem/specimen/
// pressure_boundary.h; docs/calibrate.md, "Confining boundary") against
// closed forms on a square lattice of touching disks: each side's chain is
// its outermost column, every grain of a straight column carries P d
// horizontally, a side's forces add up to P times the platen gap to
// round-off whatever the boundary's shape, a grain pushed outward is found
// and pushed back, and forces set by others stay.
#include "dem/specimen/pressure_boundary.h"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace demfem::dem;

namespace
{
  // Columns i = 0..nx-1 at x = i d, rows j = 0..ny-1 at y = (j + 1/2) d,
  // radius d/2: the platens at y = 0 and ny d touch the end rows.
  Particles<2> lattice(int nx, int ny, double d)
  {
    Particles<2> p;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        p.add(Vec<2>(i * d, (j + 0.5) * d), 0.5 * d, 2650);
    return p;
  }

  Vec<2> side_force(const Particles<2> &p, const std::vector<std::uint32_t> &chain)
  {
    Vec<2> F = Vec<2>::Zero();
    for (auto i : chain)
      F += p.f_ext[i];
    return F;
  }
} // namespace

TEST_CASE("pressure boundary: a straight column carries P d per grain, each side P H",
          "[labtests][confined][pressure]")
{
  const int        nx = 6, ny = 10;
  const double     d = 1e-3, P = 5e6, H = ny * d;
  Particles<2>     p = lattice(nx, ny, d);
  PressureBoundary b(P);
  b.apply(p, 0, H);
  for (int s = 0; s < 2; ++s)
    {
      const auto &chain = b.chain(s);
      REQUIRE(chain.size() == std::size_t(ny));
      const double inward = s ? -1.0 : 1.0;
      for (int j = 0; j < ny; ++j)
        {
          // The column's grains in height order (i = 0 left, nx-1 right).
          CHECK(chain[j] == std::uint32_t(j * nx + (s ? nx - 1 : 0)));
          // Interior: two half segments of length d; end grains: a half
          // segment and the d/2 to the platen. Exact up to round-off.
          CHECK(p.f_ext[chain[j]][0] == Approx(inward * P * d).epsilon(1e-12));
          CHECK(std::abs(p.f_ext[chain[j]][1]) < 1e-12 * P * d);
        }
      CHECK(b.pressure(s) == Approx(P).epsilon(1e-12));
    }
  // Only the outermost columns are loaded.
  for (std::size_t i = 0; i < p.size(); ++i)
    if (int(i) % nx != 0 && int(i) % nx != nx - 1)
      CHECK(p.f_ext[i].norm() == 0);
}

TEST_CASE("pressure boundary: a bulging or retreating boundary still carries P H, the "
          "grain pushed out is pushed back, other forces stay",
          "[labtests][confined][pressure]")
{
  const int    nx = 6, ny = 10;
  const double d = 1e-3, P = 5e6;
  Particles<2> p = lattice(nx, ny, d);
  // A grain of the right column pushed out by 0.3 d, one of the left
  // column pulled in by 0.6 d (its inner neighbour then reaches farther out
  // on some rays), and a force set by someone else on a boundary grain.
  const std::uint32_t out = 4 * nx + nx - 1, in = 6 * nx;
  p.x[out][0] += 0.3 * d;
  p.x[in][0] += 0.6 * d;
  const Vec<2> other(1.5, -2.5);
  p.f_ext[out] = other;
  // The platens closed a little: the gap is less than the lattice's.
  const double     y_lo = 0.1 * d, y_hi = (ny - 0.2) * d, gap = y_hi - y_lo;
  PressureBoundary b(P);
  for (int k = 0; k < 2; ++k) // applying again replaces the forces
    b.apply(p, y_lo, y_hi);
  for (int s = 0; s < 2; ++s)
    {
      const Vec<2> F = side_force(p, b.chain(s)) - (s ? other : Vec<2>::Zero());
      INFO("side " << s << ": " << F.transpose() << " N/m, chain " << b.chain(s).size());
      // Sum of d_y over the chain plus the two end pieces: the gap.
      CHECK(F[0] == Approx((s ? -1 : 1) * P * gap).epsilon(1e-12));
      CHECK(b.pressure(s) == Approx(P).epsilon(1e-12));
    }
  // The bulging grain: pushed back by P d (its two half segments' y
  // components cancel), on top of the other force.
  CHECK(p.f_ext[out][0] - other[0] == Approx(-P * d).epsilon(1e-12));
  CHECK(std::abs(p.f_ext[out][1] - other[1]) < 1e-9 * P * d);
  // The retreated grain (left surface at 0.1 d) still reaches farther out
  // on its row's rays than its inner neighbour (0.5 d): it stays on the
  // chain, and the membrane follows it in: by symmetry of its two segments
  // it carries P d inward (+x), nothing vertical.
  const auto &left = b.chain(0);
  CHECK(std::find(left.begin(), left.end(), in) != left.end());
  CHECK(p.f_ext[in][0] == Approx(P * d).epsilon(1e-12));
  CHECK(std::abs(p.f_ext[in][1]) < 1e-9 * P * d);
  b.remove(p);
  CHECK(p.f_ext[out][0] == Approx(other[0]).epsilon(1e-9));
  CHECK(p.f_ext[out][1] == Approx(other[1]).epsilon(1e-9));
  for (std::size_t i = 0; i < p.size(); ++i)
    if (i != out)
      CHECK(p.f_ext[i].norm() < 1e-9);
}
