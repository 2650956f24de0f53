#pragma once
// Small helpers shared by the subcommands' option parsing, and the one place
// where the apps turn text into numbers themselves (option values, list
// entries and the .prm keys whose pattern is free-form because they also take
// words such as 'auto'). The whole text must be the number: "0.125x", "3.5m"
// or "1.5" for an integer are errors naming the value, never 0.125, 3.5 or 1.
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace demfem::apps
{
  /// A command-line or parameter error: the message names the option or key,
  /// where it was given and what is allowed.
  struct UsageError : std::runtime_error
  {
    using std::runtime_error::runtime_error;
  };

  /// The whole of `text` as a finite number in [lo, hi]; otherwise
  /// UsageError "<what> = '<text>' is not ... (allowed: ...)". `what` names
  /// the key and where it came from; `unit` (e.g. "m") is shown with the
  /// allowed range.
  double parse_number(const std::string &what, const std::string &text,
                      double             lo   = -std::numeric_limits<double>::max(),
                      double             hi   = std::numeric_limits<double>::max(),
                      const std::string &unit = "");

  /// The whole of `text` as an integer (decimal digits, optional sign) in
  /// [lo, hi]; "1.5" or "2e3" are errors.
  long long parse_integer(const std::string &what, const std::string &text, long long lo,
                          long long hi);

  /// The entries of a comma-separated list, each trimmed of blanks; empty
  /// entries (",,", a trailing comma) are errors naming `what`.
  std::vector<std::string> split_list(const std::string &what, const std::string &text);

  /// Parses a floating-point option value; throws UsageError naming the option.
  double parse_double(const std::string &option, const std::string &value);
  /// Parses an integer option value within [lo, hi].
  long parse_int(const std::string &option, const std::string &value, long lo, long hi);
} // namespace demfem::apps
