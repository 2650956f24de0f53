#include "apps/cli.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace demfem::apps
{
  namespace
  {
    std::string range_text(double lo, double hi, const std::string &unit)
    {
      const double       big = std::numeric_limits<double>::max();
      std::ostringstream s;
      s << std::setprecision(6);
      // lo at the smallest positive doubles means "> 0" (a length, say).
      if (lo > 0 && lo < 1e-200 && hi == big)
        s << "a number > 0";
      else if (lo == -big && hi == big)
        s << "a finite number";
      else if (hi == big)
        s << "a number >= " << lo;
      else if (lo == -big)
        s << "a number <= " << hi;
      else
        s << "a number in [" << lo << ", " << hi << "]";
      if (!unit.empty())
        s << " [" << unit << "]";
      return s.str();
    }

    /// `text` without surrounding blanks (as ParameterHandler stores values
    /// read from a file; a --set value may carry them).
    std::string trimmed(const std::string &text)
    {
      const auto b = text.find_first_not_of(" \t");
      return b == std::string::npos
                 ? std::string()
                 : text.substr(b, text.find_last_not_of(" \t") - b + 1);
    }
  } // namespace

  double parse_number(const std::string &what, const std::string &text, double lo,
                      double hi, const std::string &unit)
  {
    const std::string t     = trimmed(text);
    const char       *begin = t.c_str();
    char             *end   = nullptr;
    errno                   = 0;
    const double v          = std::strtod(begin, &end);
    // strtod stops at the first foreign character: it must be the end, else
    // "0.125x" silently reads as 0.125.
    const bool whole = !t.empty() && end != begin && *end == '\0';
    if (!whole || errno == ERANGE || !std::isfinite(v))
      throw UsageError(what + " = '" + text +
                       "' is not a number (allowed: " + range_text(lo, hi, unit) + ")");
    if (v < lo || v > hi)
      throw UsageError(what + " = '" + text +
                       "' is out of range (allowed: " + range_text(lo, hi, unit) + ")");
    return v;
  }

  long long parse_integer(const std::string &what, const std::string &text, long long lo,
                          long long hi)
  {
    const std::string t     = trimmed(text);
    const char       *begin = t.c_str();
    char             *end   = nullptr;
    errno                   = 0;
    const long long v       = std::strtoll(begin, &end, 10);
    const bool      whole   = !t.empty() && end != begin && *end == '\0';
    if (!whole || errno == ERANGE || v < lo || v > hi)
      throw UsageError(what + " = '" + text + "' is not an integer in [" +
                       std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }

  std::vector<std::string> split_list(const std::string &what, const std::string &text)
  {
    std::vector<std::string> out;
    if (text.find_first_not_of(" \t") == std::string::npos)
      return out;
    std::stringstream ss(text);
    for (std::string t; std::getline(ss, t, ',');)
      {
        const auto b = t.find_first_not_of(" \t");
        if (b == std::string::npos)
          throw UsageError(what + " = '" + text +
                           "' has an empty entry (allowed: comma-separated values)");
        out.push_back(t.substr(b, t.find_last_not_of(" \t") - b + 1));
      }
    if (text.find_last_not_of(" \t") == text.rfind(','))
      throw UsageError(what + " = '" + text +
                       "' ends with a comma (allowed: comma-separated values)");
    return out;
  }

  double parse_double(const std::string &option, const std::string &value)
  {
    return parse_number("option " + option, value);
  }

  long parse_int(const std::string &option, const std::string &value, long lo, long hi)
  {
    return static_cast<long>(parse_integer("option " + option, value, lo, hi));
  }
} // namespace demfem::apps
