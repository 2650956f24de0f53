// Embedded elastic patch test (docs/architecture.md, "Verification cases"):
// unbreakable bonds, uniform hydrostatic far-field stress. A circular inclusion
// whose plane-strain bulk stiffness lambda + G equals the continuum's carries
// exactly the applied hydrostatic stress (the homogeneous field u = eps r
// satisfies equilibrium and continuity whatever G), so once the continuum is
// given the region's lambda + G the stress measured in the region must equal
// the applied one. Run 1 measures lambda + G of the packing (mean stress over
// the ring strain); run 2 uses it and checks the region stress.
#include <catch2/catch.hpp>

#include "coupling/coupled_model.h"
#include "dem/measure/particle_stress.h"
#include "helpers.h"

#include <cmath>

using namespace demfem;
using namespace demfem::coupling;

namespace
{
  struct Measured
  {
    Eigen::Matrix2d centre, rim; // stress in the centre disk and in a ring
    double          eps  = 0;    // mean radial strain of the interface
    double          ring = 0, whole = 0;
    double          jump   = 0; // largest sector jump of the radial strain
    double          grains = 0; // mean stress of the VTK averaged_stress, r < 0.6
  };

  Measured run(const std::string &variant, double E, double nu, double p,
               unsigned int subcycles = 1)
  {
    const RegionParams r = test::small_region(false, 0.5);
    ContinuumParams    c;
    c.young_modulus = E;
    c.poisson_ratio = nu;
    c.outer_radius  = 10;
    CouplingParams cp;
    cp.variant   = variant;
    cp.subcycles = subcycles;
    auto  mp     = make_coupled_model(r, c, cp, MPI_COMM_WORLD);
    auto &m      = *mp;
    m.build();
    m.set_insitu(-p * Eigen::Matrix2d::Identity());
    // Installed over 2 ms of model time, then relaxed until the grains and
    // the continuum are in equilibrium (ratios below 1e-4).
    const bool settled = test::install_insitu(m, 2e-3, 0.1);
    INFO("equilibrium reached at t = " << m.dem.time() << " s");
    CHECK(settled);
    Measured out;
    out.centre = region_stress(m.dem, dem::Vec<2>::Zero(), 0.6);
    {
      // The per-grain averaged stress written to the particles VTK (grain
      // stress x the region's solid fraction, dem/measure/particle_stress.h),
      // volume-weighted over the grains centred in the same disk.
      const auto  sg = dem::grain_stresses(m.dem, 1 - m.groups.interior_porosity);
      const auto &P  = m.dem.particles;
      double      sv = 0, v = 0;
      for (std::size_t i = 0; i < P.size(); ++i)
        if (P.x[i].norm() < 0.6)
          {
            const double vi = P.radius[i] * P.radius[i];
            sv += vi * 0.5 * sg[i].trace();
            v += vi;
          }
      out.grains = sv / v;
    }
    // Annulus 0.6 < r < ro = disk(ro) - disk(0.6), area-weighted; ro =
    // 0.85 for the wall facets, 0.1 m inside the free grains' boundary for
    // the slaved layer (0.7).
    const double          ro  = std::min(0.85, m.continuum_inner_radius() - 0.1);
    const Eigen::Matrix2d sro = region_stress(m.dem, dem::Vec<2>::Zero(), ro);
    out.rim                   = (sro * ro * ro - out.centre * 0.36) / (ro * ro - 0.36);
    const auto  u             = m.coupling_displacements();
    const auto &pts           = m.coupling_points();
    double      s             = 0;
    for (std::size_t k = 0; k < u.size(); ++k)
      s += u[k].dot(dem::Vec<2>(pts[k][0], pts[k][1])) / pts[k].norm_square();
    out.eps = s / u.size();
    // Displacement continuity across the interface: radial strain u.x/|x|^2
    // of the outer layer of free grains (centres within 1.5 mean diameters
    // of the interface: the ring, or the slaved layer's inner edge),
    // averaged per 45-degree sector, vs the coupling nodes'.
    {
      const auto  &P      = m.dem.particles;
      const double d      = m.region_params().mean_diameter();
      const double r_in   = m.continuum_inner_radius();
      double       sum[8] = {0}, cnt[8] = {0};
      for (std::size_t i = 0; i < P.size(); ++i)
        if (P.x0[i].norm() > r_in - 1.5 * d && P.x0[i].norm() < r_in)
          {
            const int k = std::min(
                7, int((std::atan2(P.x0[i][1], P.x0[i][0]) + M_PI) / (M_PI / 4)));
            sum[k] += (P.x[i] - P.x0[i]).dot(P.x0[i]) / P.x0[i].squaredNorm();
            cnt[k] += 1;
          }
      for (int k = 0; k < 8; ++k)
        out.jump = std::max(out.jump, std::abs(sum[k] / cnt[k] / out.eps - 1));
    }
    // Stress from the ring forces on the grains: (1/A) sum x (x) f.
    Eigen::Matrix2d sr = Eigen::Matrix2d::Zero();
    for (std::size_t v = 0; v < m.dem.walls.vertex.size(); ++v)
      sr -= m.dem.walls.vertex[v] * m.dem.walls.vertex_force[v].transpose();
    sr /= M_PI;
    out.ring  = 0.5 * sr.trace();
    out.whole = 0.5 * region_stress(m.dem, dem::Vec<2>::Zero(), 1.2).trace();
    INFO("final unbalanced ratio " << m.dem.unbalanced_ratio());
    CHECK(m.dem.unbalanced_ratio() < 1e-3);
    return out;
  }
} // namespace

TEST_CASE("coupling: embedded elastic patch test, hydrostatic far field",
          "[coupling][patch]")
{
  test::ensure_mpi_coupling();
  const std::string variant = GENERATE(as<std::string>{}, "wall-facets", "slaved-layer");
  INFO("Coupling/variant = " << variant);
  const double p  = 10e6;
  const double nu = 0.25;
  // Run 1: a guess of the continuum's constants.
  const Measured m1 = run(variant, 20e9, nu, p);
  const double   lg =
      0.5 * m1.centre.trace() / 2 / m1.eps; // lambda + G = sigma_m / (2 eps)
  const double E2 = lg * 2 * (1 + nu) * (1 - 2 * nu);
  INFO("run 1: centre stress " << m1.centre(0, 0) << ", " << m1.centre(1, 1) << ", "
                               << m1.centre(0, 1) << "; ring strain " << m1.eps
                               << "; lambda+G of the region " << lg << " -> E " << E2);
  REQUIRE(lg > 0);
  const Measured m2 = run(variant, E2, nu, p);
  const double   sm = 0.5 * m2.centre.trace();
  const double   dev =
      std::hypot(0.5 * (m2.centre(0, 0) - m2.centre(1, 1)), m2.centre(0, 1));
  const double rim = 0.5 * m2.rim.trace();
  INFO("ring-force mean stress " << m1.ring << " / " << m2.ring << ", whole-region Love "
                                 << m1.whole << " / " << m2.whole);
  INFO("run 2: centre mean stress " << sm << " (applied " << -p << "), deviator " << dev
                                    << ", rim mean stress " << rim);
  CHECK(std::abs(sm + p) < 0.02 * p); // region stress = applied (within 2 %)
  CHECK(dev < 0.02 * p);              // isotropic
  // Uniform: rim annulus vs centre disk. The difference is the fabric of a
  // random packing, not a trend: over packing seeds 10000, 1, 2, 3 and
  // grains of 3.5-5.3, 4-6 and 4.5-6.8 cm it measured -4.2 % to +4.1 % of
  // p, its sign changing with the seed (the slaved layer's annulus, 0.6 <
  // r < 0.7, holds about 200 grains). A rim the ring does not load, or a
  // looser carved layer, differs by tens of %.
  CHECK(std::abs(rim - sm) < 0.05 * p);
  // The VTK's averaged_stress reads as the continuum stress: it differs from
  // the Love-Weber disk stress only by the local porosity against the
  // interior's (dem_region.h, interior_porosity: the looser layer at the
  // ring left out) and the grain-centre selection: measured -1.8 % (wall
  // facets), -1.0 % (slaved; -2.1 and -2.9 % with the whole region's
  // porosity).
  INFO("grain averaged stress (VTK), mean over r < 0.6: " << m2.grains);
  CHECK(std::abs(m2.grains + p) < 0.04 * p);
  INFO("largest jump of the radial strain, outer grain layer vs ring, per sector: "
       << m2.jump);
  CHECK(m2.jump < 0.05); // displacement continuous within 5 %
}

TEST_CASE("coupling: a sub-cycled slaved layer reaches the same in-situ state",
          "[coupling][patch][subcycles]")
{
  // The lagged window of a sub-cycled continuum must stay within the coupled
  // step limit (coupled_model.cc; the study test "[subcycles]" reproduces the
  // silent failure without it). The in-situ state does not depend on k (same
  // equilibrium): 1 % (equilibrium tolerance 1e-3).
  test::ensure_mpi_coupling();
  const double   p  = 10e6;
  const Measured m1 = run("slaved-layer", 16.3e9, 0.11, p, 1);
  const Measured m4 = run("slaved-layer", 16.3e9, 0.11, p, 4);
  const double   s1 = 0.5 * m1.centre.trace(), s4 = 0.5 * m4.centre.trace();
  INFO("centre mean stress k = 1: " << s1 << ", k = 4: " << s4);
  CHECK(std::abs(s4 - s1) < 0.01 * p);
  CHECK(std::abs(m4.eps - m1.eps) < 0.01 * std::abs(m1.eps));
}
