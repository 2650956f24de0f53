// Strength envelopes (dem/specimen/envelope.h): both fits recover the parameters of a
// synthetic series exactly (to round-off), and refuse sets without an
// envelope.
#include "dem/specimen/envelope.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

using namespace demfem::dem;

TEST_CASE("Mohr-Coulomb fit recovers c and phi of a synthetic series", "[envelope]")
{
  // Granite-like: c = 30 MPa, phi = 50 deg; sigma_1 from the closed form.
  const double        c = 30e6, phi = 50 * M_PI / 180;
  const double        q  = (1 + std::sin(phi)) / (1 - std::sin(phi));
  std::vector<double> s3 = {0, 5e6, 10e6, 20e6, 40e6}, s1;
  for (double x : s3)
    s1.push_back(2 * c * std::cos(phi) / (1 - std::sin(phi)) + q * x);
  const MohrCoulombFit f = fit_mohr_coulomb(s3, s1, "test");
  // Exact data: only round-off of sums of ~1e8 Pa values (relative 1e-12).
  CHECK(f.cohesion == Approx(c).epsilon(1e-12));
  CHECK(f.friction_angle == Approx(phi).epsilon(1e-12));
  CHECK(f.q == Approx(q).epsilon(1e-12));
  CHECK(f.r2 == Approx(1).epsilon(1e-12));
  CHECK(mohr_coulomb_sigma_1(f, 15e6) == Approx(f.sigma_c + q * 15e6).epsilon(1e-14));
}

TEST_CASE("Hoek-Brown fit recovers sigma_ci and m_i of a synthetic series", "[envelope]")
{
  // Lac du Bonnet-like intact rock: sigma_ci = 200 MPa, m_i = 28.
  const double        sci = 200e6, mi = 28;
  HoekBrownFit        exact{sci, mi, 1};
  std::vector<double> s3 = {0, 5e6, 10e6, 20e6, 40e6}, s1;
  for (double x : s3)
    s1.push_back(hoek_brown_sigma_1(exact, x));
  const HoekBrownFit f = fit_hoek_brown(s3, s1, "test");
  CHECK(f.sigma_ci == Approx(sci).epsilon(1e-12));
  CHECK(f.mi == Approx(mi).epsilon(1e-11));
  CHECK(f.r2 == Approx(1).epsilon(1e-12));
  // The same points through a Mohr–Coulomb line: curvature leaves r2 < 1.
  CHECK(fit_mohr_coulomb(s3, s1, "test").r2 < 0.999);
}

TEST_CASE("envelope fits refuse sets without an envelope", "[envelope]")
{
  CHECK_THROWS_AS(fit_mohr_coulomb({10e6, 10e6}, {100e6, 110e6}, "series"),
                  std::invalid_argument);
  CHECK_THROWS_AS(fit_hoek_brown({0}, {100e6}, "series"), std::invalid_argument);
  CHECK_THROWS_AS(fit_hoek_brown({0, -5e6}, {100e6, 80e6}, "series"),
                  std::invalid_argument);
  CHECK_THROWS_WITH(fit_mohr_coulomb({0, 5e6}, {100e6, 4e6}, "Tests/confining pressures"),
                    Catch::Contains("Tests/confining pressures"));
}
