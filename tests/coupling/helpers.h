#pragma once
#include <deal.II/base/mpi.h>

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
} // namespace demfem::test
