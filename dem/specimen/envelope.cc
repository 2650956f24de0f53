// Strength envelopes of a triaxial series (see envelope.h).
#include "dem/specimen/envelope.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace demfem::dem
{
  namespace
  {
    struct Line
    {
      double intercept = 0, slope = 0, r2 = 0;
    };

    // Ordinary least squares y = a + b x with its coefficient of determination.
    Line least_squares(const std::vector<double> &x, const std::vector<double> &y)
    {
      const double n  = double(x.size());
      double       mx = 0, my = 0;
      for (std::size_t k = 0; k < x.size(); ++k)
        mx += x[k] / n, my += y[k] / n;
      double sxx = 0, sxy = 0, syy = 0;
      for (std::size_t k = 0; k < x.size(); ++k)
        sxx += (x[k] - mx) * (x[k] - mx), sxy += (x[k] - mx) * (y[k] - my),
            syy += (y[k] - my) * (y[k] - my);
      Line l;
      l.slope     = sxy / sxx;
      l.intercept = my - l.slope * mx;
      // All points on the line (syy = 0 only for a flat, exactly fitted set).
      l.r2 = syy > 0 ? sxy * sxy / (sxx * syy) : 1.0;
      return l;
    }

    void check_points(const std::vector<double> &s3, const std::vector<double> &s1,
                      const std::string &what)
    {
      if (s3.size() != s1.size())
        throw std::invalid_argument(what + ": sigma_3 and sigma_1 differ in length");
      bool distinct = false;
      for (std::size_t k = 0; k < s3.size(); ++k)
        {
          if (!(std::isfinite(s3[k]) && std::isfinite(s1[k]) && s3[k] >= 0 &&
                s1[k] > s3[k]))
            throw std::invalid_argument(
                what +
                ": each point needs finite sigma_3 >= 0 and sigma_1 > sigma_3 (point " +
                std::to_string(k) + ": sigma_3 = " + std::to_string(s3[k]) +
                ", sigma_1 = " + std::to_string(s1[k]) + ")");
          distinct = distinct || s3[k] != s3[0];
        }
      if (!distinct)
        throw std::invalid_argument(
            what + ": an envelope needs at least two distinct confining pressures");
    }
  } // namespace

  MohrCoulombFit fit_mohr_coulomb(const std::vector<double> &s3,
                                  const std::vector<double> &s1, const std::string &what)
  {
    check_points(s3, s1, what);
    const Line     l = least_squares(s3, s1);
    MohrCoulombFit f;
    f.sigma_c = l.intercept;
    f.q       = l.slope;
    f.r2      = l.r2;
    // q = (1 + sin phi)/(1 - sin phi)  <=>  sin phi = (q - 1)/(q + 1);
    // sigma_c = 2 c cos phi / (1 - sin phi) = 2 c sqrt(q). A slope <= 0 has
    // no friction angle.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    f.friction_angle = f.q > 0 ? std::asin((f.q - 1) / (f.q + 1)) : nan;
    f.cohesion       = f.q > 0 ? f.sigma_c / (2 * std::sqrt(f.q)) : nan;
    return f;
  }

  HoekBrownFit fit_hoek_brown(const std::vector<double> &s3,
                              const std::vector<double> &s1, const std::string &what)
  {
    check_points(s3, s1, what);
    std::vector<double> y(s3.size());
    for (std::size_t k = 0; k < s3.size(); ++k)
      y[k] = (s1[k] - s3[k]) * (s1[k] - s3[k]);
    const Line   l   = least_squares(s3, y);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    HoekBrownFit f;
    f.sigma_ci = l.intercept > 0 ? std::sqrt(l.intercept) : nan;
    f.mi       = l.intercept > 0 ? l.slope / f.sigma_ci : nan;
    f.r2       = l.r2;
    return f;
  }

  double mohr_coulomb_sigma_1(const MohrCoulombFit &f, double s3)
  {
    return f.sigma_c + f.q * s3;
  }

  double hoek_brown_sigma_1(const HoekBrownFit &f, double s3)
  {
    return s3 + f.sigma_ci * std::sqrt(f.mi * s3 / f.sigma_ci + 1);
  }
} // namespace demfem::dem
