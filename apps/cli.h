#pragma once
// Small helpers shared by the subcommands' option parsing.
#include <stdexcept>
#include <string>

namespace demfem::apps
{
  /// A command-line error: the message names the option and what is allowed.
  struct UsageError : std::runtime_error
  {
    using std::runtime_error::runtime_error;
  };

  /// Parses a floating-point option value; throws UsageError naming the option.
  double parse_double(const std::string &option, const std::string &value);
  /// Parses an integer option value within [lo, hi].
  long parse_int(const std::string &option, const std::string &value, long lo, long hi);
} // namespace demfem::apps
