#pragma once
// Strength envelopes of a triaxial series (docs/calibrate.md, "Triaxial
// series and envelope"): Mohr–Coulomb and Hoek–Brown fitted to the peak
// stresses. Compression positive: sigma_3 is the confining pressure, sigma_1
// the peak axial stress.
#include <string>
#include <vector>

namespace demfem::dem
{
  /// Mohr–Coulomb in principal stresses, sigma_1 = sigma_c + q sigma_3 with
  /// q = (1 + sin phi) / (1 - sin phi) and sigma_c = 2 c sqrt(q).
  struct MohrCoulombFit
  {
    double sigma_c        = 0; ///< intercept: unconfined strength of the line [Pa]
    double q              = 0; ///< slope d sigma_1 / d sigma_3
    double cohesion       = 0; ///< c [Pa]
    double friction_angle = 0; ///< phi [rad]
    double r2             = 0; ///< coefficient of determination of sigma_1
  };

  /// Hoek–Brown for intact rock (s = 1, a = 1/2):
  /// sigma_1 = sigma_3 + sigma_ci sqrt(m_i sigma_3 / sigma_ci + 1), fitted
  /// as Hoek & Brown (1997) do: (sigma_1 - sigma_3)^2 is linear in sigma_3
  /// with intercept sigma_ci^2 and slope m_i sigma_ci.
  struct HoekBrownFit
  {
    double sigma_ci = 0; ///< [Pa]
    double mi       = 0;
    double r2       = 0; ///< of the linear regression of (sigma_1 - sigma_3)^2
  };

  /// Least-squares fits to the points (sigma_3[k], sigma_1[k]); both need at
  /// least two distinct sigma_3 >= 0 and sigma_1 > sigma_3 (a std::invalid_argument
  /// names `what` otherwise). A Hoek–Brown intercept <= 0 (no real sigma_ci)
  /// gives NaN sigma_ci and m_i.
  MohrCoulombFit fit_mohr_coulomb(const std::vector<double> &sigma_3,
                                  const std::vector<double> &sigma_1,
                                  const std::string         &what);
  HoekBrownFit   fit_hoek_brown(const std::vector<double> &sigma_3,
                                const std::vector<double> &sigma_1,
                                const std::string         &what);

  /// The envelopes' sigma_1 at sigma_3.
  double mohr_coulomb_sigma_1(const MohrCoulombFit &f, double sigma_3);
  double hoek_brown_sigma_1(const HoekBrownFit &f, double sigma_3);
} // namespace demfem::dem
