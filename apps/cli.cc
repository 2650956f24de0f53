#include "apps/cli.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace demfem::apps
{
  double parse_double(const std::string &option, const std::string &value)
  {
    char *end = nullptr;
    errno     = 0;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || errno != 0 || !std::isfinite(v))
      throw UsageError("option " + option + ": '" + value + "' is not a finite number");
    return v;
  }

  long parse_int(const std::string &option, const std::string &value, long lo, long hi)
  {
    char *end = nullptr;
    errno     = 0;
    const long v = std::strtol(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || errno != 0 || v < lo || v > hi)
      throw UsageError("option " + option + ": '" + value + "' must be an integer in [" +
                       std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }
} // namespace demfem::apps
