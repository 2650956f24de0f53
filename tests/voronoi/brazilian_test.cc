// Brazilian test on rigid and flexible Voronoi grains
// (dem/voronoi/voronoi_lab_test.h, VoronoiTest::brazilian): disk specimen,
// flat gap-based platens.
#include "dem/engine/types.h"
#include "dem/voronoi/voronoi_lab_test.h"

#include "voronoi_test_helpers.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <optional>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;
using namespace demfem::dem::voronoi::testing;

namespace
{
  const VoronoiSpecimen &disk()
  {
    static const VoronoiSpecimen s = [] {
      VoronoiSpecimenParams p;
      p.width    = 0.04;
      p.height   = 0.04;
      p.n_grains = 260;
      return make_voronoi_disk_specimen(p);
    }();
    return s;
  }

  ContactMaterial breakable()
  {
    ContactMaterial m;
    m.contact_modulus         = 50e9;
    m.kratio                  = 1.5;
    m.tensile_strength        = 2.5e6;
    m.cohesion                = 7.5e6;
    m.friction                = 0.5;
    m.thickness               = 1;
    m.tensile_fracture_energy = 1;
    m.shear_fracture_energy   = 10;
    return m;
  }
} // namespace

TEST_CASE("Voronoi disk specimen: cells fill the circle, centres inside",
          "[voronoi][lab][brazilian]")
{
  const auto &s = disk();
  double      A = 0;
  for (double a : s.tessellation.area)
    A += a;
  CHECK(A == Approx(s.domain.area()).epsilon(1e-12));
  for (std::size_t i = 0; i < s.x.size(); ++i)
    CHECK(std::hypot(s.x[i] - s.domain.cx, s.y[i] - s.domain.cy) < s.domain.radius);
  CHECK(s.tessellation.n_cells() > 150);
}

TEST_CASE("Voronoi Brazilian test: splits along the loaded diameter, BTS independent of "
          "the time step",
          "[voronoi][lab][brazilian]")
{
  const auto      &s = disk();
  VoronoiLabParams p;
  p.test            = VoronoiTest::brazilian;
  p.strain_rate     = 1.0;
  p.strain_limit    = 5e-3;
  p.platen_friction = 0.5; // holds the disk laterally
  p.safety          = 0.5;
  std::optional<RigidVoronoiModel> m;
  const auto                       a = run_voronoi_lab_test(s, breakable(), 2650, p, &m);
  p.safety                           = 0.8;
  const auto b                       = run_voronoi_lab_test(s, breakable(), 2650, p);
  INFO("BTS " << a.peak_stress << " / " << b.peak_stress << " Pa, F " << a.peak_force
              << " N at " << a.peak_strain << ", steps " << a.loading_steps << " / "
              << b.loading_steps << ", cracks " << a.cracks_tensile << " + "
              << a.cracks_shear);
  REQUIRE(a.status == VoronoiLabStatus::ok);
  CHECK(a.ended_by == "post-peak");
  // fistPkg Eq. 24 with the disk of the specimen.
  CHECK(a.peak_stress ==
        Approx(a.peak_force / (M_PI * s.domain.radius * 1.0)).epsilon(1e-12));
  // Same loading path integrated with dt and 1.6 dt (measured 8e-4); 0.5 %.
  CHECK(b.peak_stress == Approx(a.peak_stress).epsilon(0.005));
  // The tensile stress across the loaded diameter splits the disk: the
  // cracked points lie near the vertical diameter. The band |x - cx| < R/4
  // holds about 31 % of the disk; measured 88 % of the cracked points.
  const auto &c    = m->contacts;
  double      near = 0, all = 0;
  for (int k = 0; k < c.n_contacts(); ++k)
    for (int q = c.point_offset[k]; q < c.point_offset[k + 1]; ++q)
      if (c.crack[q] == PointCrack::tensile || c.crack[q] == PointCrack::shear)
        {
          const double xm = 0.5 * (m->x[c.grain_a[k]] + m->x[c.grain_b[k]]);
          all += 1;
          near += std::abs(xm - s.domain.cx) < s.domain.radius / 4;
        }
  CHECK(all > 0);
  CHECK(near > 0.7 * all);
  CHECK(a.cracks_tensile > a.cracks_shear);
}

TEST_CASE("Voronoi Brazilian test: the specimen shape is checked",
          "[voronoi][lab][brazilian]")
{
  VoronoiLabParams p;
  p.test = VoronoiTest::brazilian;
  VoronoiSpecimen rect;
  rect.x            = {0.25, 0.75, 0.25, 0.75};
  rect.y            = {0.25, 0.25, 0.75, 0.75};
  rect.radius       = {0.2, 0.2, 0.2, 0.2};
  rect.domain       = ClipDomain::rectangle(0, 0, 1, 1);
  rect.tessellation = laguerre_tessellation(rect.x, rect.y, rect.radius, rect.domain);
  CHECK_THROWS_AS(run_voronoi_lab_test(rect, breakable(), 2650, p), InputError);
  GrainElasticity g;
  g.youngs_modulus = 50e9;
  g.density        = 2650;
  CHECK_THROWS_AS(run_flexible_voronoi_lab_test(rect, breakable(), g, p), InputError);
  p.test = VoronoiTest::unconfined_compression;
  CHECK_THROWS_AS(run_voronoi_lab_test(disk(), breakable(), 2650, p), InputError);
  CHECK_THROWS_AS(run_flexible_voronoi_lab_test(disk(), breakable(), g, p), InputError);
}

TEST_CASE("Voronoi Brazilian test with stiff flexible grains: the rigid grains' BTS",
          "[voronoi][lab][brazilian][flexible]")
{
  // Seed 004 §2.2: the flexible model tends to the rigid one for stiff
  // grains. Grain E = 100 E_c; a small coarse disk (51 grains) at 2/s and
  // edges merged at 0.2 of the mean cell diameter keep the run short (the
  // element time step of such stiff grains is ~1/26 of the rigid one:
  // 115 000 steps against 4400).
  static const VoronoiSpecimen s = [] {
    VoronoiSpecimenParams q;
    q.width    = 0.03;
    q.height   = 0.03;
    q.n_grains = 65;
    return make_voronoi_disk_specimen(q, 128);
  }();
  VoronoiLabParams p;
  p.test                            = VoronoiTest::brazilian;
  p.strain_rate                     = 2.0;
  p.strain_limit                    = 5e-3;
  p.platen_friction                 = 0.5;
  p.flexible_mesh.min_edge_fraction = 0.2;
  const GrainElasticity g           = grain_elasticity(100 * breakable().contact_modulus);
  const auto            rigid       = run_voronoi_lab_test(s, breakable(), 2650, p);
  const auto            flex        = run_flexible_voronoi_lab_test(s, breakable(), g, p);
  INFO("grains " << flex.n_grains << ", BTS rigid " << rigid.peak_stress << " Pa at "
                 << rigid.peak_strain << " (" << rigid.loading_steps
                 << " steps), flexible " << flex.peak_stress << " Pa at "
                 << flex.peak_strain << " (" << flex.loading_steps << " steps, "
                 << flex.ended_by << "), ratio " << flex.peak_stress / rigid.peak_stress);
  REQUIRE(rigid.status == VoronoiLabStatus::ok);
  REQUIRE(flex.status == VoronoiLabStatus::ok);
  CHECK(flex.ended_by == "post-peak");
  CHECK(flex.peak_force > 0);
  CHECK(flex.peak_stress ==
        Approx(flex.peak_force / (M_PI * s.domain.radius * 1.0)).epsilon(1e-12));
  CHECK(flex.cracks_tensile + flex.cracks_shear > 0);
  // Measured flexible / rigid BTS: 1.0004 here (1.0015 with merging at
  // 0.1); 1.0047 on the 260-grain disk of the test above at 1/s (merging
  // 0.05 and 0.1; 1.003 with E = 10 E_c). Tolerance 2 %, four times the
  // largest of them.
  CHECK(flex.peak_stress == Approx(rigid.peak_stress).epsilon(0.02));
}
