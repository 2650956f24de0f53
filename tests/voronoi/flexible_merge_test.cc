// Merging of short cell edges in the flexible grains (dem/voronoi/
// flexible_grain.h; docs/voronoi.md, "Short cell edges"): the merged mesh
// keeps the grains' masses, maps every cell vertex to a node of its grain,
// and lifts the stable time step of a genesis specimen.
#include "dem/engine/types.h"
#include "dem/voronoi/flexible_model.h"
#include "dem/voronoi/voronoi_lab_test.h"

#include "voronoi_test_helpers.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;
using namespace demfem::dem::voronoi::testing;

namespace
{
  /// Elastic, elastically uniform contacts (kappa = 1, kn = E_c / d).
  ContactMaterial elastic()
  {
    ContactMaterial m;
    m.contact_modulus  = 50e9;
    m.kratio           = 1;
    m.tensile_strength = 1e12;
    m.cohesion         = 1e12;
    m.friction         = 0.5;
    m.thickness        = 1;
    return m;
  }
} // namespace

TEST_CASE("Flexible grains with merged short edges: masses, vertex map, coarse edges",
          "[voronoi][flexible][merge]")
{
  const auto       &s = lab_specimen();
  const auto       &t = s.tessellation;
  const auto        g = grain_elasticity(50e9);
  const double      f = 0.1;
  FlexibleGrainMesh merged(t, g, FlexibleMeshOptions{f}), full(t, g, {0.0});
  REQUIRE(merged.n_nodes() < full.n_nodes());
  // Total mass rho t x (domain area): every grain keeps the mass of its
  // cell (roundoff of ~1000 lumped masses: 1e-12).
  double mass = 0, min_ratio = 1;
  for (double m : merged.mass)
    mass += m;
  CHECK(mass == Approx(g.density * g.thickness * s.domain.area()).epsilon(1e-12));
  for (int c = 0; c < t.n_cells(); ++c)
    {
      double mc = 0, area = 0;
      for (int a = merged.grain_node_offset[c]; a < merged.grain_node_offset[c + 1]; ++a)
        mc += merged.mass[a];
      for (int e = merged.grain_triangle_offset[c];
           e < merged.grain_triangle_offset[c + 1]; ++e)
        area += merged.triangle_area0[e];
      CHECK(mc == Approx(g.density * g.thickness * t.area[c]).epsilon(1e-12));
      // The coarse polygon lies inside the cell and cuts little of it.
      CHECK(area <= t.area[c] * (1 + 1e-12));
      min_ratio = std::min(min_ratio, area / t.area[c]);
      for (int e = t.begin(c); e < t.end(c); ++e)
        {
          const int n = merged.vertex_node[e];
          CHECK(merged.node_grain[n] == c);
          CHECK(n > merged.grain_node_offset[c]); // a boundary node
          // A vertex is at most a merge distance or so from its node.
          CHECK(std::hypot(merged.x0[n] - t.vertex_x[e], merged.y0[n] - t.vertex_y[e]) <=
                merged.merge_distance);
        }
    }
  // Coarse edges shorter than the merge distance remain only where the
  // three-node floor or a fan triangle forbade the merge: few.
  int short_edges = 0, edges = 0;
  for (int c = 0; c < t.n_cells(); ++c)
    {
      const int n0 = merged.grain_node_offset[c],
                k  = merged.grain_node_offset[c + 1] - n0 - 1;
      for (int j = 0; j < k; ++j)
        {
          const int a = n0 + 1 + j, b = n0 + 1 + (j + 1) % k;
          short_edges += std::hypot(merged.x0[b] - merged.x0[a],
                                    merged.y0[b] - merged.y0[a]) < merged.merge_distance;
          ++edges;
        }
    }
  // Measured 0.94 (a small cell whose corners are cut at a tenth of the
  // mean diameter); no coarse edge below the merge distance.
  INFO("smallest coarse / cell area " << min_ratio);
  CHECK(min_ratio > 0.9);
  INFO(short_edges << " of " << edges << " coarse edges below " << merged.merge_distance);
  CHECK(short_edges <= edges / 100);
}

TEST_CASE("Flexible grains with merged short edges: the stable time step rises",
          "[voronoi][flexible][merge]")
{
  const auto          &s = lab_specimen();
  FlexibleVoronoiModel full(s.tessellation, s.x, s.y, s.radius, grain_elasticity(50e9),
                            elastic(), PointScheme::lobatto3, FlexibleMeshOptions{0.0});
  // The default merge fraction (0.1).
  FlexibleVoronoiModel merged(s.tessellation, s.x, s.y, s.radius, grain_elasticity(50e9),
                              elastic());
  const double         dt0 = full.stable_time_step(), dt1 = merged.stable_time_step();
  INFO("stable time step " << dt0 << " s unmerged, " << dt1 << " s merged");
  // Measured 1.25e-9 and 3.10e-8 s: 24.8 x. Asked: 16 x.
  CHECK(dt1 > 16 * dt0);
}

TEST_CASE("Flexible grains: measure the merge fraction's time step and UCS modulus",
          "[.measure][voronoi][flexible][merge]")
{
  // By hand (docs/voronoi.md, "Short cell edges"): elastic UCS at 1 and
  // 0.25/s to a strain of 2e-4 on the 200-grain specimen, grain E = E_c =
  // 50 GPa.
  const auto      &s = lab_specimen();
  VoronoiLabParams p;
  p.test         = VoronoiTest::unconfined_compression;
  p.strain_limit = 2e-4;
  for (double rate : {1.0, 0.25})
    for (double f : {0.0, 0.05, 0.1, 0.2})
      {
        p.strain_rate                     = rate;
        p.flexible_mesh.min_edge_fraction = f;
        const auto start                  = std::chrono::steady_clock::now();
        const auto r =
            run_flexible_voronoi_lab_test(s, elastic(), grain_elasticity(50e9), p);
        const double sec =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                .count();
        FlexibleGrainMesh mesh(s.tessellation, grain_elasticity(50e9),
                               FlexibleMeshOptions{f});
        std::cout << "rate " << rate << ", fraction " << f << ": nodes " << mesh.n_nodes()
                  << ", dt " << r.time_step << " s, steps " << r.loading_steps << ", E "
                  << r.E << ", nu " << r.nu << ", " << sec << " s\n";
      }
}

TEST_CASE("Flexible grains with merged short edges: side edges keep their geometry",
          "[voronoi][flexible][merge]")
{
  // A side edge whose ends were merged into one node (collapsed on the mesh;
  // the genesis specimen above has none: its shortest side edge is 1.9 mm
  // against a merge distance of 0.56 mm at 0.2) keeps its tessellation ends
  // through the stencils of the triangles that hold them, so a pressure on
  // a side gives the exact resultant and moment of the uniform traction.
  // Jittered lattices, the first seed with a collapsed side edge.
  const double h = 1e-3;
  for (std::uint64_t seed = 1; seed < 40; ++seed)
    {
      const Packing p = jittered(6, 8, seed, 0.2, h);
      const auto   &x = p.x, &y = p.y, &r = p.r;
      const double  W = p.W, H = p.H;
      const auto    t = laguerre_tessellation(x, y, r, ClipDomain::rectangle(0, 0, W, H));
      FlexibleVoronoiModel m(t, x, y, r, grain_elasticity(50e9), elastic(),
                             PointScheme::lobatto3, FlexibleMeshOptions{0.2});
      double               xmin, ymin, xmax, ymax;
      int                  collapsed = 0;
      for (const SideEdge &e : rectangle_side_edges(t, xmin, ymin, xmax, ymax))
        collapsed +=
            m.mesh.vertex_node[e.edge] == m.mesh.vertex_node[t.next(e.cell, e.edge)];
      if (collapsed == 0)
        continue;
      INFO("seed " << seed << ": " << collapsed << " side edges collapsed");
      for (const auto &b : m.boundary_edges)
        {
          const double dx = m.point_x(b.end[1]) - m.point_x(b.end[0]);
          const double dy = m.point_y(b.end[1]) - m.point_y(b.end[0]);
          CHECK(std::hypot(dx, dy) == Approx(b.length).epsilon(1e-9));
        }
      for (Side side : {Side::left, Side::bottom})
        {
          const double p = 1e6;
          m.set_pressure(Side::left, side == Side::left ? p : 0);
          m.set_pressure(Side::bottom, side == Side::bottom ? p : 0);
          m.compute_forces(0.0); // undeformed, at rest: the pressure only
          double Fx = 0, Fy = 0, M = 0;
          for (int a = 0; a < m.mesh.n_nodes(); ++a)
            {
              Fx += m.fx[a];
              Fy += m.fy[a];
              M += m.x[a] * m.fy[a] - m.y[a] * m.fx[a];
            }
          // Thickness 1. Left: traction p x on x = 0, F = p H x, M = -p H^2 / 2;
          // bottom: p y on y = 0, F = p W y, M = p W^2 / 2. Roundoff of ~100
          // node forces: 1e-12.
          const double L = side == Side::left ? H : W;
          CHECK(std::abs(Fx - (side == Side::left ? p * L : 0)) <= 1e-12 * p * L);
          CHECK(std::abs(Fy - (side == Side::left ? 0 : p * L)) <= 1e-12 * p * L);
          const double Me = (side == Side::left ? -0.5 : 0.5) * p * L * L;
          CHECK(std::abs(M - Me) <= 1e-12 * p * L * L);
        }
      return;
    }
  FAIL("no lattice with a collapsed side edge");
}
