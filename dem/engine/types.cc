#include "dem/engine/types.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace demfem::dem
{
  namespace
  {
    std::string bound(double v)
    {
      if (v == std::numeric_limits<double>::infinity())
        return "inf";
      if (v == -std::numeric_limits<double>::infinity())
        return "-inf";
      std::ostringstream s;
      s << v;
      return s.str();
    }
  } // namespace

  void check_range(const std::string &where,
                   const std::string &name,
                   double value,
                   double lo,
                   double hi,
                   bool lo_open,
                   bool hi_open)
  {
    const bool ok = std::isfinite(value) || (std::isinf(value) && value == hi && !hi_open);
    const bool above = lo_open ? value > lo : value >= lo;
    const bool below = hi_open ? value < hi : value <= hi;
    if (!(ok && above && below))
      {
        std::ostringstream msg;
        msg << where << ": parameter '" << name << "' = " << value
            << " is outside the allowed range " << (lo_open ? "(" : "[")
            << bound(lo) << ", " << bound(hi) << (hi_open ? ")" : "]");
        throw InputError(msg.str());
      }
  }
} // namespace demfem::dem
