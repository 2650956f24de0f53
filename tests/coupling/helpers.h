#pragma once
#include <deal.II/base/mpi.h>

#include "coupling/coupled_model.h"

namespace demfem::test
{
  // MPI for the deal.II distributed objects of the coupled model; finalized
  // at exit.
  inline void ensure_mpi_coupling()
  {
    static int                                      argc   = 1;
    static char                                     name[] = "test_coupling";
    static char                                    *args[] = {name, nullptr};
    static char                                   **argv   = args;
    static dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  }

  // The small verification region of the coupling tests (about 330 grains):
  // radius 1 m, grains 8-12 cm, E* = 20 GPa.
  inline coupling::RegionParams small_region(bool breakable = false)
  {
    coupling::RegionParams r;
    r.radius    = 1.0;
    r.d_lo      = 0.08;
    r.d_hi      = 0.12;
    r.emod      = 20e9;
    r.lnm_emod  = 20e9;
    r.breakable = breakable;
    return r;
  }

  // Plane-strain continuum to R = 10 m around it.
  inline coupling::ContinuumParams continuum(double E, double nu)
  {
    coupling::ContinuumParams c;
    c.young_modulus = E;
    c.poisson_ratio = nu;
    c.outer_radius  = 10;
    return c;
  }
} // namespace demfem::test
