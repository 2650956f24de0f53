// The 3D embedded DEM region (coupling/dem_region.h): spheres packed by
// the calibration's genesis (grain scaling to the material pressure) in a
// box the slab's thickness, carved to the cylinder r < b inside a lateral
// ring of triangle facets, between two frictionless planar slab walls,
// bonded with 3D flat joints (Nr x Nal elements).
#include <catch2/catch.hpp>

#include "coupling/dem_region.h"

#include <algorithm>
#include <cmath>

using namespace demfem;
using namespace demfem::coupling;

namespace
{
  // Radius 0.6 m, grains 8-12 cm, slab 4 mean diameters thick: about 500
  // spheres (packing about 10 s on one core).
  RegionParams slab_region()
  {
    RegionParams r;
    r.radius         = 0.6;
    r.d_lo           = 0.08;
    r.d_hi           = 0.12;
    r.emod           = 20e9;
    r.lnm_emod       = 20e9;
    r.breakable      = false;
    r.slab_thickness = 0.4;
    return r;
  }

  struct Built
  {
    dem::Model<3> model;
    RegionGroups  groups;
    int           ring = -1;
  };

  // The ring: facets about two mean grain diameters long, two layers.
  void build(Built &b, const RegionParams &p)
  {
    b.ring = add_cylinder_ring(b.model.walls, p.radius, p.slab_thickness, 20, 2, "ring");
    b.groups = build_region<3>(b.model, p);
  }

  double max_contact_force(const dem::Model<3> &m)
  {
    double f = 0;
    for (int g = 0; g < m.n_groups(); ++g)
      for (std::size_t k = 0; k < m.group(g).size(); ++k)
        f = std::max(f, m.group(g).force[k].norm());
    return f;
  }
} // namespace

TEST_CASE("3D region: the genesis packs the slab jammed, every grain inside the slab, "
          "force-free at the start",
          "[coupling][region3d]")
{
  const RegionParams p = slab_region();
  Built              b;
  build(b, p);
  const auto &P = b.model.particles;
  const auto &G = b.groups;
  INFO(P.size() << " grains, " << G.n_bonds << " bonds, " << G.n_rattlers
                << " rattlers; porosity packed " << G.packed_porosity << ", final "
                << G.porosity << "; overlap/r mean " << G.mean_overlap_ratio << " max "
                << G.max_overlap_ratio);
  REQUIRE(P.size() > 300);
  // The keys' material is packed by the calibration's genesis to its
  // material pressure (auto: lnm emod / 800) in a box the slab's thickness
  // and carved: a jammed frictionless packing of spheres, looser than in
  // bulk (0.36) by the layers along the slab walls. Measured 0.411 packed,
  // 0.47 carved (the rim's cut and moved grains).
  CHECK(G.packed_porosity > 0.36);
  CHECK(G.packed_porosity < 0.45);
  // Rattlers: a frictionless jammed packing leaves a few per cent loose
  // (measured 3.6 %).
  CHECK(G.n_rattlers < 0.06 * (P.size() + G.n_rattlers));
  CHECK(G.porosity >= G.packed_porosity);
  // Just jammed, not crushed: at Pm = E* / 800 the mean overlap is a few
  // tenths of a per cent of the radius (measured 0.33 %).
  CHECK(G.mean_overlap_ratio > 0.001);
  CHECK(G.mean_overlap_ratio < 0.01);
  // Mean coordination of the bonded grains: a frictionless jammed packing of
  // spheres is isostatic, 6 contacts per grain in bulk; grains on the walls
  // have fewer (measured 5.25).
  CHECK(2.0 * G.n_bonds / P.size() > 4.5);
  CHECK(G.slab_walls[0] >= 0);
  CHECK(G.slab_walls[1] >= 0);

  // Every grain inside: clear of each ring facet and of both slab walls.
  const auto  &W     = b.model.walls;
  const double t     = p.slab_thickness;
  double       worst = HUGE_VAL; // smallest clearance / radius
  for (std::size_t i = 0; i < P.size(); ++i)
    {
      CHECK(P.x[i].head<2>().norm() < p.radius);
      worst = std::min(
          {worst, P.x[i][2] / P.radius[i] - 1, (t - P.x[i][2]) / P.radius[i] - 1});
      for (std::size_t k = 0; k < W.n_facets(); ++k)
        if (W.facet_wall[k] == b.ring)
          {
            std::array<double, 3> wgt;
            const double          d = (W.closest_point(k, P.x[i], wgt) - P.x[i]).norm();
            worst                   = std::min(worst, d / P.radius[i] - 1);
          }
    }
  INFO("smallest grain-wall clearance / radius " << worst);
  // Smoothing leaves gaps >= 0 (shrunk by 1.0000001 times the overlap);
  // 1e-12 allows the round-off of the closest-point computation.
  CHECK(worst > -1e-12);

  // Bonded at zero force: 500 steps from rest move nothing. Flat joints are
  // installed with zero relative displacement, wall contacts were opened by
  // the smoothing, other contacts are apart: every force is exactly 0.
  b.model.cycle(500);
  const double fmax = max_contact_force(b.model);
  INFO("largest contact force after 500 steps: " << fmax << " N");
  CHECK(fmax == 0);
  CHECK(b.model.kinetic_energy() == 0);
}

TEST_CASE("3D region: the slab walls hold the grains without friction, Love-Weber "
          "stress of the slab",
          "[coupling][region3d]")
{
  RegionParams p = slab_region();
  p.wall_fric    = 0; // frictionless ring: the slab walls alone carry g_z
  Built b;
  build(b, p);
  auto        &m = b.model;
  const auto  &P = m.particles;
  const double g = 2000; // [m/s^2]: forces far above round-off
  m.gravity      = dem::Vec<3>(0.3 * g, 0, -g);
  double mass = 0, mz = 0, mx = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    mass += P.mass[i];
  for (int n = 0; n < 400 && (n < 5 || m.unbalanced_ratio() > 1e-6); ++n)
    m.cycle(100);
  INFO("unbalanced ratio " << m.unbalanced_ratio() << " after " << m.step_count()
                           << " steps");
  REQUIRE(m.unbalanced_ratio() < 1e-5);

  // The grains stay between the slab walls.
  for (std::size_t i = 0; i < P.size(); ++i)
    {
      REQUIRE(P.x[i][2] > 0);
      REQUIRE(P.x[i][2] < p.slab_thickness);
      mz += P.mass[i] * P.x[i][2];
      mx += P.mass[i] * P.x[i][0];
    }
  // Every slab-wall contact, including those made during the settling, is
  // under the frictionless slab law (dem::Model::new_wall_contact_law).
  std::size_t n_slab = 0;
  for (int gr = 0; gr < m.n_groups(); ++gr)
    for (std::size_t k = 0; k < m.group(gr).size(); ++k)
      if (m.group(gr).is_wall[k])
        {
          const int w = m.walls.facet_wall[m.group(gr).end2[k]];
          if (w == b.groups.slab_walls[0] || w == b.groups.slab_walls[1])
            {
              CHECK(gr == b.groups.slab_wall);
              ++n_slab;
            }
        }
  CHECK(n_slab > 50);

  // Vertical load on the slab walls, horizontal on the ring; frictionless
  // slab walls take no horizontal force at all (exactly 0).
  const dem::Vec<3> bottom = m.walls.wall_force(b.groups.slab_walls[0]),
                    top    = m.walls.wall_force(b.groups.slab_walls[1]),
                    ring   = m.walls.wall_force(b.ring);
  INFO("weight " << mass * g << " N; bottom " << bottom.transpose() << "; top "
                 << top.transpose() << "; ring " << ring.transpose());
  // (Round-off only: the contact normal of a planar facet has x, y parts of
  // 1e-16.)
  CHECK(bottom.head<2>().norm() < 1e-12 * mass * g);
  CHECK(top.head<2>().norm() < 1e-12 * mass * g);
  // At equilibrium within the unbalanced ratio (1e-5 of the mean contact
  // force, summed over ~500 grains): 1e-3 relative.
  CHECK((bottom + top)[2] == Approx(-mass * g).epsilon(1e-3));
  CHECK(ring[0] == Approx(0.3 * mass * g).epsilon(1e-3));

  // Love-Weber identity at equilibrium: summing (x_c - x_p) f_pc over all
  // contacts (what region_stress does) equals the boundary and body-force
  // moments sum_walls x_c f^T + sum_p x_p m_p g^T, so over a cylinder
  // holding every contact szz = -g sum m_p z_p / V and sxz = (sum_walls +
  // 0.3 g sum m_p z_p - g sum m_p x_p) / 2V. Checked for szz, whose wall
  // part is the bottom wall at z = 0 (x_c z = 0 up to half an overlap).
  const double          r = 1.01 * p.radius, V = M_PI * r * r * p.slab_thickness;
  const Eigen::Matrix3d s = region_stress(m, dem::Vec<3>::Zero(), r, p.slab_thickness);
  INFO("region stress\n" << s);
  CHECK(s(2, 2) == Approx(-g * mz / V).epsilon(2e-3));
  // Lateral (Poisson) stress in the gravity-compressed slab: compressive.
  CHECK(s(0, 0) < 0);
  (void)mx;
}
