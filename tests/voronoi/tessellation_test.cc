// Laguerre tessellation (dem/voronoi/tessellation.h, docs/voronoi.md):
// areas sum to the domain, every disk of a non-overlapping packing lies in
// its own cell, shared edges agree from both sides and lie on the power
// bisector, cells agree with a brute-force nearest-power-distance search,
// a square lattice gives square cells, and empty (hidden, outside) cells are
// reported.
#include "dem/engine/types.h"
#include "dem/voronoi/tessellation.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;

namespace
{
  struct Packing
  {
    std::vector<double> x, y, r;
  };

  /// Random sequential addition of non-overlapping disks, radii uniform in
  /// [rmin, rmax], centres inside [0, W] x [0, H] (disks may cross the
  /// boundary, as in a specimen cut from a larger packing).
  Packing random_packing(double W, double H, double rmin, double rmax, int target,
                         unsigned seed)
  {
    std::mt19937                           gen(seed);
    std::uniform_real_distribution<double> ux(0, W), uy(0, H), ur(rmin, rmax);
    Packing                                p;
    for (int attempt = 0; attempt < 200 * target && (int)p.x.size() < target; ++attempt)
      {
        const double x = ux(gen), y = uy(gen), r = ur(gen);
        bool         free = true;
        for (std::size_t j = 0; j < p.x.size() && free; ++j)
          free = std::hypot(x - p.x[j], y - p.y[j]) > r + p.r[j];
        if (free)
          {
            p.x.push_back(x);
            p.y.push_back(y);
            p.r.push_back(r);
          }
      }
    return p;
  }

  double power(const Packing &p, int i, double x, double y)
  {
    return (x - p.x[i]) * (x - p.x[i]) + (y - p.y[i]) * (y - p.y[i]) - p.r[i] * p.r[i];
  }

  /// Signed distance of (px, py) to the left of the directed edge a->b.
  double left_distance(double ax, double ay, double bx, double by, double px, double py)
  {
    const double L = std::hypot(bx - ax, by - ay);
    return ((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / L;
  }

  /// Smallest signed distance of a point to the edges of cell c (> 0 inside).
  double inside_margin(const Tessellation &t, int c, double px, double py)
  {
    double m = HUGE_VAL;
    for (int e = t.begin(c); e < t.end(c); ++e)
      {
        const int f = t.next(c, e);
        m = std::min(m, left_distance(t.vertex_x[e], t.vertex_y[e], t.vertex_x[f],
                                      t.vertex_y[f], px, py));
      }
    return m;
  }
} // namespace

TEST_CASE("Laguerre cells of a random packing: areas, seeds inside, shared edges",
          "[voronoi][tessellation]")
{
  const double W = 0.1, H = 0.2;
  const auto   p = random_packing(W, H, 1e-3, 4e-3, 400, 12345u);
  REQUIRE(p.x.size() > 300);
  const auto t = laguerre_tessellation(p.x, p.y, p.r, ClipDomain::rectangle(0, 0, W, H));
  const int  n = t.n_cells();
  REQUIRE(n == (int)p.x.size());
  // Non-overlapping disks are never hidden (the radical axis of two disjoint
  // disks separates them) and all centres are inside the domain.
  CHECK(t.empty_cells.empty());

  // Areas: each cell is computed separately, so the sum is not an identity;
  // the error is roundoff of O(n) shoelace sums of O(1e-2)-sized
  // coordinates, 1e-12 relative leaves a margin of ~1e3 over eps * n.
  double sum = 0;
  for (int c = 0; c < n; ++c)
    sum += t.area[c];
  CHECK(std::abs(sum - W * H) <= 1e-12 * W * H);

  const double L = std::hypot(W, H);
  for (int c = 0; c < n; ++c)
    {
      // The whole disk lies in its cell: every edge is at least R from the
      // centre, up to roundoff (1e-12 L); the centroid is inside too.
      double margin = inside_margin(t, c, p.x[c], p.y[c]);
      for (int e = t.begin(c); e < t.end(c); ++e)
        if (t.edge_neighbour[e] != Tessellation::boundary)
          {
            const int    f = t.next(c, e);
            const double d = left_distance(t.vertex_x[e], t.vertex_y[e], t.vertex_x[f],
                                           t.vertex_y[f], p.x[c], p.y[c]);
            CHECK(d >= p.r[c] - 1e-12 * L);
          }
      CHECK(margin > 0);
      CHECK(inside_margin(t, c, t.centroid_x[c], t.centroid_y[c]) > 0);

      for (int e = t.begin(c); e < t.end(c); ++e)
        {
          const int d = t.edge_neighbour[e];
          if (d == Tessellation::boundary)
            continue;
          // Both sides list the edge, with the endpoints in reverse order
          // (both cells are counter-clockwise); the endpoints are computed
          // independently in each cell, so they agree to roundoff (1e-12 L).
          const int g = t.shared_edge(d, c);
          REQUIRE(g >= 0);
          const int f = t.next(c, e), h = t.next(d, g);
          CHECK(std::abs(t.vertex_x[e] - t.vertex_x[h]) <= 1e-12 * L);
          CHECK(std::abs(t.vertex_y[e] - t.vertex_y[h]) <= 1e-12 * L);
          CHECK(std::abs(t.vertex_x[f] - t.vertex_x[g]) <= 1e-12 * L);
          CHECK(std::abs(t.vertex_y[f] - t.vertex_y[g]) <= 1e-12 * L);
          CHECK(std::abs(t.edge_length[e] - t.edge_length[g]) <= 1e-12 * L);
          // The edge lies on the power bisector of c and d (power values are
          // O(L^2), roundoff 1e-12 L^2).
          CHECK(std::abs(power(p, c, t.vertex_x[e], t.vertex_y[e]) -
                         power(p, d, t.vertex_x[e], t.vertex_y[e])) <= 1e-12 * L * L);
          // ... and is perpendicular to the line of centres (seed 004 §2.3:
          // the contact plane is the cell edge, its normal the centre line).
          const double ex = t.vertex_x[f] - t.vertex_x[e],
                       ey = t.vertex_y[f] - t.vertex_y[e];
          const double cx = p.x[d] - p.x[c], cy = p.y[d] - p.y[c];
          CHECK(std::abs(ex * cx + ey * cy) <=
                1e-10 * std::hypot(ex, ey) * std::hypot(cx, cy));
        }
    }

  // Independent check without CGAL: random points belong to the cell of the
  // disk of least power distance (brute force); points within 1e-9 L of an
  // edge are skipped as ties.
  std::mt19937                           gen(7u);
  std::uniform_real_distribution<double> ux(0, W), uy(0, H);
  int                                    checked = 0;
  for (int k = 0; k < 2000; ++k)
    {
      const double qx = ux(gen), qy = uy(gen);
      int          best = 0;
      for (int i = 1; i < n; ++i)
        if (power(p, i, qx, qy) < power(p, best, qx, qy))
          best = i;
      const double m = inside_margin(t, best, qx, qy);
      if (std::abs(m) < 1e-9 * L)
        continue;
      ++checked;
      CHECK(m > 0);
    }
  CHECK(checked > 1990);
}

TEST_CASE("Laguerre cells of a square lattice of equal disks are squares",
          "[voronoi][tessellation]")
{
  // nx x ny disks of radius r at spacing h in [0, nx h] x [0, ny h]: every
  // cell is the h x h square around its disk. Four cells meet at each
  // lattice corner, so the regular triangulation's diagonals give
  // zero-length edges that must be dropped.
  const int    nx = 7, ny = 5;
  const double h = 2e-3, r = 0.9e-3;
  Packing      p;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      {
        p.x.push_back((i + 0.5) * h);
        p.y.push_back((j + 0.5) * h);
        p.r.push_back(r);
      }
  const auto t =
      laguerre_tessellation(p.x, p.y, p.r, ClipDomain::rectangle(0, 0, nx * h, ny * h));
  REQUIRE(t.empty_cells.empty());
  for (int c = 0; c < t.n_cells(); ++c)
    {
      const int i = c % nx, j = c / nx;
      // Area and centroid to roundoff of coordinates of size nx h (1e-12).
      CHECK(std::abs(t.area[c] - h * h) <= 1e-12 * h * h);
      CHECK(std::abs(t.centroid_x[c] - p.x[c]) <= 1e-12 * h);
      CHECK(std::abs(t.centroid_y[c] - p.y[c]) <= 1e-12 * h);
      REQUIRE(t.end(c) - t.begin(c) == 4);
      int n_inner = 0;
      for (int e = t.begin(c); e < t.end(c); ++e)
        {
          CHECK(std::abs(t.edge_length[e] - h) <= 1e-12 * h);
          const int d = t.edge_neighbour[e];
          if (d == Tessellation::boundary)
            continue;
          ++n_inner;
          // Only the four lattice neighbours, never a diagonal one.
          const int di = d % nx - i, dj = d / nx - j;
          CHECK(std::abs(di) + std::abs(dj) == 1);
        }
      const int expected = (i > 0) + (i < nx - 1) + (j > 0) + (j < ny - 1);
      CHECK(n_inner == expected);
    }
}

TEST_CASE("Laguerre cells: hidden, duplicate and outside disks are reported",
          "[voronoi][tessellation]")
{
  // Disk 3 (r = 0.1 at the origin) is hidden by disks 0-2 (R = 1.1 at unit
  // distance, directions q_k 120 degrees apart): its cell would need
  // 2 x.q_k <= |q_k|^2 - 1.21 + 0.01 = -0.2 for all k, and the three
  // inequalities sum to 0 <= -0.6. Disk 5 duplicates disk 4. Disk 6's cell
  // lies beyond the power bisector with disk 4 (x = 11.5), outside the
  // domain. (One disk dominating another is not enough to hide it in 2D:
  // its cell is then a half-plane.)
  const double              s3  = std::sqrt(3.0) / 2;
  const std::vector<double> x   = {0.0, -s3, s3, 0.0, 3.0, 3.0, 20.0};
  const std::vector<double> y   = {1.0, -0.5, -0.5, 0.0, 0.0, 0.0, 0.0};
  const std::vector<double> r   = {1.1, 1.1, 1.1, 0.1, 0.3, 0.3, 0.3};
  const auto                dom = ClipDomain::rectangle(-2, -2, 4, 2);
  const auto                t   = laguerre_tessellation(x, y, r, dom);
  for (int c : {0, 1, 2})
    CHECK(t.empty_reason[c] == EmptyCellReason::none);
  CHECK(t.empty_reason[3] == EmptyCellReason::hidden);
  CHECK(t.empty_reason[6] == EmptyCellReason::outside_domain);
  // Exactly one of the duplicates keeps a cell.
  CHECK(((t.empty_reason[4] == EmptyCellReason::none) !=
         (t.empty_reason[5] == EmptyCellReason::none)));
  CHECK(t.empty_cells.size() == 3);
  double sum = 0;
  for (int c = 0; c < t.n_cells(); ++c)
    {
      if (t.empty_reason[c] != EmptyCellReason::none)
        {
          CHECK(t.area[c] == 0);
          CHECK(t.end(c) == t.begin(c));
        }
      sum += t.area[c];
    }
  CHECK(std::abs(sum - dom.area()) <= 1e-12 * dom.area());
  // Nothing references an empty cell; disks 0-2 meet at one point (their
  // power centre, the origin by symmetry), so each has the other two as
  // neighbours.
  for (std::size_t e = 0; e < t.edge_neighbour.size(); ++e)
    if (t.edge_neighbour[e] >= 0)
      CHECK(t.empty_reason[t.edge_neighbour[e]] == EmptyCellReason::none);
  CHECK(t.shared_edge(0, 1) >= 0);
  CHECK(t.shared_edge(1, 2) >= 0);
  CHECK(t.shared_edge(2, 0) >= 0);
}

TEST_CASE("Laguerre cells clipped to a circle", "[voronoi][tessellation]")
{
  const double R = 0.05;
  auto         p = random_packing(2 * R, 2 * R, 1e-3, 3e-3, 300, 99u);
  for (auto &v : p.x)
    v -= R;
  for (auto &v : p.y)
    v -= R;
  const auto dom       = ClipDomain::circle(0, 0, R, 128);
  const auto t         = laguerre_tessellation(p.x, p.y, p.r, dom);
  double     sum       = 0;
  int        n_outside = 0;
  for (int c = 0; c < t.n_cells(); ++c)
    {
      sum += t.area[c];
      n_outside += t.empty_reason[c] == EmptyCellReason::outside_domain;
      CHECK(t.empty_reason[c] != EmptyCellReason::hidden);
      for (int e = t.begin(c); e < t.end(c); ++e)
        CHECK(std::hypot(t.vertex_x[e], t.vertex_y[e]) <= R * (1 + 1e-12));
    }
  // Disks in the corners of the square outside the circle: some of their
  // cells miss the circle entirely, and must be reported, not crash.
  CHECK(n_outside > 0);
  CHECK(std::abs(sum - dom.area()) <= 1e-12 * dom.area());
}

TEST_CASE("Laguerre tessellation input errors", "[voronoi][tessellation]")
{
  const auto dom = ClipDomain::rectangle(0, 0, 1, 1);
  CHECK_THROWS_AS(laguerre_tessellation({0.5}, {0.5, 0.2}, {0.1}, dom), InputError);
  CHECK_THROWS_AS(laguerre_tessellation({0.5}, {0.5}, {-0.1}, dom), InputError);
  CHECK_THROWS_AS(laguerre_tessellation({NAN}, {0.5}, {0.1}, dom), InputError);
  CHECK_THROWS_AS(
      laguerre_tessellation({0.5}, {0.5}, {0.1}, ClipDomain::rectangle(0, 0, 0, 1)),
      InputError);
  // A single disk owns the whole domain.
  const auto t = laguerre_tessellation({0.3}, {0.4}, {0.1}, dom);
  CHECK(t.area[0] == Approx(1.0).epsilon(1e-15));
  CHECK(t.end(0) - t.begin(0) == 4);
}

TEST_CASE(
    "Laguerre cells of overlapping polydisperse disks: hidden cells, areas, ownership",
    "[voronoi][tessellation]")
{
  // Overlaps allowed and radii over a decade: some small disks inside big
  // ones have empty power cells. Everything else must still hold.
  std::mt19937                           gen(2024u);
  std::uniform_real_distribution<double> u(0, 0.1), ur(0.5e-3, 8e-3);
  Packing                                p;
  for (int i = 0; i < 600; ++i)
    {
      p.x.push_back(u(gen));
      p.y.push_back(u(gen));
      p.r.push_back(ur(gen));
    }
  const auto t =
      laguerre_tessellation(p.x, p.y, p.r, ClipDomain::rectangle(0, 0, 0.1, 0.1));
  int    n_hidden = 0;
  double sum      = 0;
  for (int c = 0; c < t.n_cells(); ++c)
    {
      n_hidden += t.empty_reason[c] == EmptyCellReason::hidden;
      sum += t.area[c];
      for (int e = t.begin(c); e < t.end(c); ++e)
        {
          const int d = t.edge_neighbour[e];
          if (d == Tessellation::boundary)
            continue;
          CHECK(t.empty_reason[d] == EmptyCellReason::none);
          CHECK(t.shared_edge(d, c) >= 0);
        }
    }
  CHECK(n_hidden > 0);
  // Same roundoff argument as for the non-overlapping packing.
  CHECK(std::abs(sum - 0.01) <= 1e-12 * 0.01);
  // Brute-force ownership: the disk of least power distance owns the point
  // (a hidden disk never does).
  const double                           L = 0.1 * std::sqrt(2.0);
  std::uniform_real_distribution<double> uq(0, 0.1);
  int                                    checked = 0;
  for (int k = 0; k < 2000; ++k)
    {
      const double qx = uq(gen), qy = uq(gen);
      int          best = 0;
      for (int i = 1; i < t.n_cells(); ++i)
        if (power(p, i, qx, qy) < power(p, best, qx, qy))
          best = i;
      REQUIRE(t.empty_reason[best] == EmptyCellReason::none);
      const double m = inside_margin(t, best, qx, qy);
      if (std::abs(m) < 1e-9 * L)
        continue;
      ++checked;
      CHECK(m > 0);
    }
  CHECK(checked > 1990);
}
