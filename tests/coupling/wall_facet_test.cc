// Wall-facet coupling (docs/architecture.md, "Wall facets"): force balance
// across the interface and the embedded elastic patch test.
#include <catch2/catch.hpp>

#include "coupling/wall_facet_model.h"
#include "helpers.h"

#include <cmath>

using namespace demfem;
using namespace demfem::coupling;

TEST_CASE("wall facets: DEM force sum on the ring equals the continuum's nodal force sum "
          "every step",
          "[coupling]")
{
  test::ensure_mpi_coupling();
  for (unsigned int k : {1u, 3u})
    {
      CouplingParams cp;
      cp.subcycles = k;
      WallFacetModel<2> m(test::small_region(false), test::continuum(20e9, 0.25), cp,
                          MPI_COMM_WORLD);
      m.build();
      Eigen::Matrix2d s0;
      s0 << -10e6, 2e6, 2e6, -5e6;
      m.set_insitu(s0);
      double worst = 0;
      for (int n = 0; n < 1500; ++n)
        {
          m.set_load_factor(std::min(1.0, n / 1000.0));
          m.step();
          worst = std::max(worst, m.imbalance_last());
        }
      INFO("subcycles " << k << ": max relative imbalance " << worst);
      CHECK(m.dem.walls.wall_force(m.ring_wall()).norm() > 0); // the ring is loaded
      CHECK(worst == m.imbalance_max());
      CHECK(worst < 1e-10);
    }
}
