// Slaved-layer coupling (docs/architecture.md, "Slaved layer";
// coupling/slaved_layer_model.h): force balance across the interface,
// slaved-slaved contacts transfer nothing, divergence detected.
#include <catch2/catch.hpp>

#include "coupling/slaved_layer_model.h"
#include "helpers.h"

#include <cmath>

using namespace demfem;
using namespace demfem::coupling;

TEST_CASE("slaved layer: DEM force sum on the slaved grains equals the continuum's nodal "
          "force sum every step",
          "[coupling][slaved]")
{
  test::ensure_mpi_coupling();
  for (unsigned int k : {1u, 3u})
    {
      CouplingParams cp;
      cp.subcycles = k;
      SlavedLayerModel<2> m(test::small_region(), test::continuum(20e9, 0.25), cp,
                            MPI_COMM_WORLD);
      m.build();
      REQUIRE(m.n_slaved() > 50);
      Eigen::Matrix2d s0;
      s0 << -10e6, 2e6, 2e6, -5e6;
      m.set_insitu(s0);
      double worst = 0, loaded = 0;
      for (int n = 0; n < 1500; ++n)
        {
          m.set_load_factor(std::min(1.0, n / 1000.0));
          m.step();
          worst  = std::max(worst, m.imbalance_last());
          loaded = std::max(loaded, m.interface_force().norm());
        }
      // The slaved grains are loaded by the free ones: sum |f| over the
      // slaved grains, a scale for the (cancelling) resultant.
      double sum_abs = 0;
      for (std::size_t i = 0; i < m.dem.particles.size(); ++i)
        if (m.dem.particles.group[i] == SlavedLayerModel<2>::slaved_tag)
          sum_abs += m.dem.particles.f[i].norm();
      INFO("subcycles " << k << ": max relative imbalance " << worst
                        << ", sum |f| on slaved grains " << sum_abs);
      CHECK(sum_abs > 1e5); // 10 MPa on a 1 m disk: ~1e7 N in total
      CHECK(worst == m.imbalance_max());
      CHECK(worst < 1e-10); // partition of unity: round-off only
      // Null group: slaved-slaved contacts exist and carry nothing.
      const auto &null = m.dem.group(m.null_group());
      REQUIRE(null.size() > 0);
      double null_force = 0;
      for (std::size_t c = 0; c < null.size(); ++c)
        null_force = std::max(null_force, null.force[c].norm());
      CHECK(null_force == 0);
    }
}

// With every free grain removed, the only contacts are slaved-slaved: the
// continuum must receive exactly zero force and deform as the bare annulus
// b - h <= r <= R with a traction-free inner boundary and the far field
// displaced by eps r (Lame: u = A r + B / r, sigma_rr(b - h) = 0).
TEST_CASE("slaved layer: slaved-slaved contacts transfer no force to the continuum",
          "[coupling][slaved]")
{
  test::ensure_mpi_coupling();
  const double        E = 20e9, nu = 0.25, p = 10e6;
  SlavedLayerModel<2> m(test::small_region(), test::continuum(E, nu), CouplingParams{},
                        MPI_COMM_WORLD);
  m.build();
  auto             &P = m.dem.particles;
  std::vector<char> rm(P.size());
  std::size_t       n_free = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    n_free += (rm[i] = P.group[i] != SlavedLayerModel<2>::slaved_tag);
  REQUIRE(n_free > 100);
  m.dem.remove_particles(rm);
  m.dem.reset_energy_baseline();
  m.set_insitu(-p * Eigen::Matrix2d::Identity());
  double largest = 0;
  for (int n = 0; n < 6000; ++n)
    {
      m.set_load_factor(std::min(1.0, n / 2000.0));
      m.step();
      largest = std::max(largest, m.interface_force().norm());
      for (std::size_t i = 0; i < P.size(); ++i)
        largest = std::max(largest, P.f[i].norm() + std::abs(P.m[i][0]));
    }
  CHECK(largest == 0); // nothing at all reaches the continuum
  // Radial strain of the slaved grains vs the Lame solution.
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), G = E / (2 * (1 + nu));
  const double eps = -p * (1 + nu) * (1 - 2 * nu) / E; // plane-strain hydrostatic
  const double a = m.continuum_inner_radius(), R = 10;
  const double ratio = (lambda + G) / G * a * a; // B = ratio A
  const double A     = eps * R / (R + ratio / R);
  double       err = 0, mean = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    {
      const double r = P.x0[i].norm(), ur = (P.x[i] - P.x0[i]).dot(P.x0[i]) / r;
      const double exact = A * r + ratio * A / r;
      err                = std::max(err, std::abs(ur / exact - 1));
      mean += ur / exact / P.size();
    }
  INFO("slaved grains " << P.size() << ": u_r / Lame mean " << mean << ", worst " << err);
  // Q1 on cells two grain diameters wide next to the free inner boundary,
  // plus the dynamic residual after 4000 equilibrium steps: measured mean
  // -0.8 %, worst grain 1.3 %.
  CHECK(std::abs(mean - 1) < 0.02);
  CHECK(err < 0.03);
}

TEST_CASE("slaved layer: a time-step safety far above 1 is detected as divergence",
          "[coupling][slaved]")
{
  test::ensure_mpi_coupling();
  CouplingParams cp;
  cp.safety = 5;
  SlavedLayerModel<2> m(test::small_region(), test::continuum(20e9, 0.25), cp,
                        MPI_COMM_WORLD);
  m.build();
  m.set_insitu(-10e6 * Eigen::Matrix2d::Identity());
  std::string what;
  int         n = 0;
  try
    {
      for (; n < 20000; ++n)
        {
          m.set_load_factor(std::min(1.0, n / 1000.0));
          m.step();
        }
    }
  catch (const dem::InstabilityError &e)
    {
      what = e.what();
    }
  INFO("stopped at step " << n << ": " << what);
  REQUIRE_FALSE(what.empty());
  CHECK(n < 20000);
  // The diagnosis names the cause.
  CHECK((what.find("time step") != std::string::npos ||
         what.find("timestep") != std::string::npos));
}

TEST_CASE("slaved layer: an overlap leaving no free core is refused with the key named",
          "[coupling][slaved]")
{
  test::ensure_mpi_coupling();
  CouplingParams cp;
  cp.overlap_grains = 6; // 0.6 m of a 1 m region: more than half
  SlavedLayerModel<2> m(test::small_region(), test::continuum(20e9, 0.25), cp,
                        MPI_COMM_WORLD);
  try
    {
      m.build();
      FAIL("an overlap of 6 grains in a 1 m region was accepted");
    }
  catch (const dem::InputError &e)
    {
      CHECK(std::string(e.what()).find("Coupling/overlap grains") != std::string::npos);
    }
}
