// Automatic mass scaling of the explicit continuum (coupling/coupled_model.h,
// ContinuumParams::mass_scaling; docs/tunnel.md, "Where the steps go"): the
// continuum's static response does not depend on its mass, so a lighter
// continuum must reach the same equilibrium as the physical one, in fewer
// DEM steps.
#include <catch2/catch.hpp>

#include "coupling/coupled_model.h"
#include "helpers.h"

#include <algorithm>
#include <cmath>

using namespace demfem;
using namespace demfem::coupling;

namespace
{
  struct Settled
  {
    std::vector<dem::Vec<2>> u; // coupling-node displacements
    Eigen::Matrix2d          centre;
    int                      steps = 0;
    double                   mass_scaling = 0, timestep = 0;
  };

  // Hydrostatic 10 MPa ramped over 2000 steps, then cycled until the tunnel
  // phases' equilibrium (coupling/tunnel_phase.h): unbalanced ratio below
  // 1e-4 and the continuum's kinetic energy down to 1e-4 of its peak.
  Settled settle(const std::string &variant, double mass_scaling)
  {
    ContinuumParams c = test::continuum(12e9, 0.25);
    c.mass_scaling    = mass_scaling;
    CouplingParams cp;
    cp.variant = variant;
    auto  mp   = make_coupled_model(test::small_region(), c, cp, MPI_COMM_WORLD);
    auto &m    = *mp;
    m.build();
    m.set_insitu(-10e6 * Eigen::Matrix2d::Identity());
    Settled s;
    double  peak = 0;
    for (s.steps = 0; s.steps < 40000; ++s.steps)
      {
        m.set_load_factor(std::min(1.0, s.steps / 2000.0));
        m.step();
        if (s.steps % 100 == 0)
          {
            const double ke = m.continuum_kinetic_energy();
            peak            = std::max(peak, ke);
            if (s.steps > 2000 && m.dem.unbalanced_ratio() < 1e-4 && ke <= 1e-4 * peak)
              break;
          }
      }
    s.u            = m.coupling_displacements();
    s.centre       = region_stress(m.dem, dem::Vec<2>::Zero(), 0.6);
    s.timestep     = m.dt();
    s.mass_scaling = mass_scaling;
    return s;
  }
} // namespace

TEST_CASE("coupling: automatic mass scaling reaches the physical continuum's equilibrium "
          "in fewer steps",
          "[coupling][mass-scaling]")
{
  test::ensure_mpi_coupling();
  const Settled physical = settle("slaved-layer", 1.0);
  const Settled scaled   = settle("slaved-layer", 0.0); // automatic
  double        diff = 0, scale = 0;
  for (std::size_t k = 0; k < physical.u.size(); ++k)
    {
      diff  = std::max(diff, (physical.u[k] - scaled.u[k]).norm());
      scale = std::max(scale, physical.u[k].norm());
    }
  const double sp = 0.5 * physical.centre.trace(), ss = 0.5 * scaled.centre.trace();
  INFO("physical: " << physical.steps << " steps, centre mean stress " << sp
                    << "; automatic: " << scaled.steps << " steps, centre " << ss
                    << "; interface displacement difference " << diff / scale
                    << "; time steps " << physical.timestep << " / " << scaled.timestep);
  // Both end at the same static state within the equilibrium tolerances
  // (ratio 1e-4, kinetic energy 1e-4 of its peak: the quasi-static scheme
  // and the explicit one agree to 2e-3 at such tolerances,
  // tests/coupling/quasi_static_test.cc).
  CHECK(diff / scale < 2e-3);
  CHECK(std::abs(ss / sp - 1) < 2e-3);
  // The same DEM time step: the scaling stops where the continuum would
  // limit it.
  CHECK(scaled.timestep == Approx(physical.timestep).epsilon(1e-12));
  // And fewer steps.
  CHECK(scaled.steps < physical.steps);
}

TEST_CASE("coupling: automatic mass scaling is refused where it is not stable",
          "[coupling][mass-scaling]")
{
  // Wall facets: the grain-facet contacts are not in the coupled critical
  // step, and a lighter continuum went silently wrong (centre stress
  // -597 MPa for -10 MPa); the quasi-static scheme has no inertia to scale.
  for (const auto &[variant, scheme] : {std::pair<std::string, std::string>{"wall-facets",
                                                                            "explicit"},
                                        {"slaved-layer", "quasi-static"}})
    {
      ContinuumParams c = test::continuum(12e9, 0.25);
      c.mass_scaling    = 0;
      CouplingParams cp;
      cp.variant = variant;
      cp.scheme  = scheme;
      INFO(variant << ", " << scheme);
      try
        {
          c.validate("test", 2, 1.0, cp);
          FAIL("automatic mass scaling accepted");
        }
      catch (const dem::InputError &e)
        {
          CHECK(std::string(e.what()).find("Continuum/mass scaling") != std::string::npos);
        }
      c.mass_scaling = 1;
      CHECK_NOTHROW(c.validate("test", 2, 1.0, cp));
    }
}
