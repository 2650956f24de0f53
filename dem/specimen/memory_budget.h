#pragma once
// Memory budget of a DEM model (docs/architecture.md, "Input validation"):
// the grain count of a specimen or region is estimated before anything is
// allocated, and a model that would not fit is refused naming the key that
// sets the grain size and the key of the limit, instead of a bare
// std::bad_alloc after minutes of packing.
#include "dem/engine/types.h"

#include <unistd.h>

#include <cmath>
#include <sstream>
#include <string>

namespace demfem::dem
{
  /// Resident memory per grain of a flat-jointed assembly with its contacts
  /// and law state: measured 5.6 kB (3D, 8-element joints) and 2.2 kB (2D)
  /// as the slope of the peak resident size of `demfem bench dem --material`
  /// between 2e4 and 8e4 grains (docs/bench.md), with 40 % headroom for the
  /// packing's transient contacts and the checkpoint copies.
  constexpr double bytes_per_grain(int dim) { return dim == 2 ? 3.1e3 : 7.9e3; }

  /// Half the machine's physical memory [bytes] (infinite if unknown): the
  /// default limit, leaving room for the continuum and the rest.
  inline double default_memory_limit()
  {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? 0.5 * double(pages) * double(page) : HUGE_VAL;
  }

  /// Refuses (InputError) a model of about `n_grains` grains whose estimated
  /// memory exceeds `limit` bytes (<= 0: default_memory_limit()).
  inline void check_memory(double n_grains, int dim, double limit,
                           const std::string &where, const std::string &size_key,
                           const std::string &limit_key)
  {
    if (!(limit > 0))
      limit = default_memory_limit();
    const double need = n_grains * bytes_per_grain(dim);
    if (!(need <= limit))
      {
        std::ostringstream m;
        m.precision(3);
        m << where << ": about " << n_grains << " grains would need about " << need / 1e9
          << " GB, above the memory limit of " << limit / 1e9 << " GB (" << limit_key
          << "; default: half the machine's memory); raise " << size_key
          << " (larger grains) or the limit";
        throw InputError(m.str());
      }
  }
} // namespace demfem::dem
