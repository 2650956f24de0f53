#pragma once
// Output helpers of `demfem calibrate`: a small JSON writer (numbers stay
// numbers, full precision), the history CSV and a dependency-free SVG plot
// of a stress-strain curve.
#include "dem/lab_tests.h"

#include <string>
#include <utility>
#include <vector>

namespace demfem::apps
{
  /// Flat-or-nested JSON object built in order of insertion.
  class Json
  {
  public:
    Json       &num(const std::string &key, double v); ///< null if not finite
    Json       &str(const std::string &key, const std::string &v);
    Json       &obj(const std::string &key, const Json &v);
    std::string text(int indent = 0) const;

  private:
    std::vector<std::pair<std::string, std::string>> items_; // key, encoded value
    std::vector<bool>                                is_obj_;
    std::vector<Json>                                objs_;
  };

  /// history_<test>.csv: one row per recorded step (header names with units).
  std::string history_csv(const std::vector<dem::HistoryRow> &h);

  /// SVG line plot of y(x) with axes, ticks and labels.
  std::string svg_plot(const std::string &title, const std::string &xlabel,
                       const std::string &ylabel, const std::vector<double> &x,
                       const std::vector<double> &y);
} // namespace demfem::apps
