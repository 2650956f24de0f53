#pragma once
// Seed statistics (docs/study.md, "Breakable mode"): the mean of n
// independent packings and its two-sided confidence interval from Student's
// t distribution with n - 1 degrees of freedom (Boost.Math, header-only):
//   mean +- t_{(1 + level)/2, n-1} s / sqrt(n),  s the sample deviation.
// With fewer than two values the interval is unknown (NaN half-width) and
// contains nothing.
#include <boost/math/distributions/students_t.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace demfem::statistics
{
  /// The two-sided critical value t_{(1 + level)/2, dof} of Student's t
  /// distribution (dof > 0, not necessarily whole: Welch's dof is not).
  inline double student_t_critical(double dof, double level)
  {
    return boost::math::quantile(boost::math::students_t(dof), 0.5 * (1 + level));
  }

  struct Interval
  {
    double      mean       = std::numeric_limits<double>::quiet_NaN();
    double      half_width = std::numeric_limits<double>::quiet_NaN();
    double      sd         = std::numeric_limits<double>::quiet_NaN();
    std::size_t n          = 0;
    /// Whether x lies in [mean - half_width, mean + half_width].
    bool contains(double x) const { return std::abs(x - mean) <= half_width; }
  };

  /// Mean and `level` confidence interval (0 < level < 1) of `values`.
  inline Interval mean_interval(const std::vector<double> &values, double level = 0.95)
  {
    Interval r;
    r.n = values.size();
    if (r.n == 0)
      return r;
    double sum = 0;
    for (double x : values)
      sum += x;
    r.mean = sum / r.n;
    if (r.n < 2)
      return r;
    double ss = 0;
    for (double x : values)
      ss += (x - r.mean) * (x - r.mean);
    r.sd = std::sqrt(ss / (r.n - 1));
    r.half_width =
        student_t_critical(double(r.n - 1), level) * r.sd / std::sqrt(double(r.n));
    return r;
  }

  /// Two seed means compared by Welch's t test: their difference, its
  /// standard error sqrt(s_a^2 / n_a + s_b^2 / n_b) (independent packings),
  /// and whether the difference lies within t_{(1 + level)/2, nu} standard
  /// errors, nu the Welch-Satterthwaite degrees of freedom
  ///   nu = se^4 / ((s_a^2/n_a)^2 / (n_a - 1) + (s_b^2/n_b)^2 / (n_b - 1)).
  /// With three packings a side the scatters are themselves uncertain (nu
  /// about 2-4), so t is 2.8-4.3, not the normal 1.96: two standard errors
  /// would call equal means different in 12-14 % of comparisons instead of
  /// 5 %. A side of one packing has no scatter of its own: the caller passes
  /// the other side's, and nu = n - 1 of that side. Without scatter on
  /// either side only equal means agree.
  struct MeanComparison
  {
    double difference         = std::numeric_limits<double>::quiet_NaN(); ///< a - b
    double standard_error     = std::numeric_limits<double>::quiet_NaN();
    double degrees_of_freedom = std::numeric_limits<double>::quiet_NaN();
    double critical           = std::numeric_limits<double>::quiet_NaN(); ///< t
    bool   agree              = false;
  };

  inline MeanComparison compare_means(double mean_a, double sd_a, std::size_t n_a,
                                      double mean_b, double sd_b, std::size_t n_b,
                                      double level = 0.95)
  {
    MeanComparison c;
    c.difference = mean_a - mean_b;
    if (n_a == 0 || n_b == 0 || (n_a < 2 && n_b < 2) || !(sd_a >= 0) || !(sd_b >= 0))
      return c;
    const double va = sd_a * sd_a / double(n_a), vb = sd_b * sd_b / double(n_b);
    c.standard_error = std::sqrt(va + vb);
    if (!(c.standard_error > 0))
      {
        c.agree = c.difference == 0;
        return c;
      }
    if (n_b < 2)
      c.degrees_of_freedom = double(n_a - 1);
    else if (n_a < 2)
      c.degrees_of_freedom = double(n_b - 1);
    else
      c.degrees_of_freedom =
          (va + vb) * (va + vb) / (va * va / double(n_a - 1) + vb * vb / double(n_b - 1));
    c.critical = student_t_critical(c.degrees_of_freedom, level);
    c.agree    = std::abs(c.difference) <= c.critical * c.standard_error;
    return c;
  }

  /// A property measured twice on the same packings (e.g. at a loading rate
  /// and at half of it): the relative change of its mean, b against a, with
  /// the standard error from the per-packing differences (paired samples,
  /// so the packings' own scatter cancels), and whether the change is
  /// within `tolerance`, t = t_{(1 + level)/2, n-1} (Student: the standard
  /// error is estimated from the n differences themselves; 4.30 at three
  /// packings, where a normal 2 would decide wrongly far more often than
  /// 1 - level):
  ///   "moves"          |change| - t se > tolerance,
  ///   "does not move"  |change| + t se <= tolerance,
  ///   "undecided"      otherwise (too few packings for the tolerance).
  struct PairedChange
  {
    double      change         = std::numeric_limits<double>::quiet_NaN();
    double      standard_error = std::numeric_limits<double>::quiet_NaN();
    double      critical       = std::numeric_limits<double>::quiet_NaN(); ///< t
    std::size_t n              = 0;
    const char *verdict        = "undecided";
  };

  inline PairedChange paired_change(const std::vector<double> &a,
                                    const std::vector<double> &b, double tolerance,
                                    double level = 0.95)
  {
    PairedChange c;
    if (a.size() != b.size() || a.empty())
      return c;
    c.n = a.size();
    std::vector<double> d;
    for (std::size_t k = 0; k < a.size(); ++k)
      d.push_back(b[k] - a[k]);
    const double mean_a = mean_interval(a).mean;
    const auto   di     = mean_interval(d);
    c.change            = di.mean / mean_a;
    if (c.n < 2)
      return c;
    c.standard_error = di.sd / std::sqrt(double(c.n)) / std::abs(mean_a);
    c.critical       = student_t_critical(double(c.n - 1), level);
    const double hw  = c.critical * c.standard_error;
    if (std::abs(c.change) - hw > tolerance)
      c.verdict = "moves";
    else if (std::abs(c.change) + hw <= tolerance)
      c.verdict = "does not move";
    return c;
  }
} // namespace demfem::statistics
