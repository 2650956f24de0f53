// Crack initiation from the crack volumetric strain
// (dem/specimen/crack_initiation.h) on synthetic loading branches whose
// elastic part and dilatancy are known in closed form.
#include "dem/specimen/crack_initiation.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace demfem::dem;

namespace
{
  constexpr double E = 50e9, nu = 0.25;

  /// Axial stress from sigma0 down by 0.1 MPa per row to sigma0 - 100 MPa
  /// (the peak, last row), lateral stress held; elastic strains of E, nu
  /// with k lateral directions, plus a dilatancy c (q - q_ci)^2 once the
  /// deviator q exceeds q_ci, plus `noise` (uniform, relative to the
  /// elastic volumetric strain at the peak).
  CompressionBranch branch(int k, double sigma0, double q_ci, double noise = 0)
  {
    CompressionBranch                      b;
    const double                           c = 1e-18; // 1/Pa^2: 3.6e-3 at the peak
    std::mt19937_64                        rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    const double                           scale = (1 - k * nu) * 100e6 / E;
    for (int i = 0; i <= 1000; ++i)
      {
        const double q   = 0.1e6 * i;
        const double ea  = -q / E;
        const double dil = q > q_ci ? c * (q - q_ci) * (q - q_ci) : 0;
        b.axial_stress.push_back(sigma0 - q);
        b.load.push_back(q);
        b.volumetric_strain.push_back(0.001 + ea * (1 - k * nu) + dil +
                                      noise * scale * u(rng));
      }
    b.peak_row = 1000;
    return b;
  }

  /// Deviator at which c (q - q_ci)^2 reaches `fraction` of the elastic
  /// volumetric strain at the peak, (1 - k nu) 100 MPa / E.
  double expected(int k, double q_ci, double fraction)
  {
    const double elastic = (1 - k * nu) * 100e6 / E;
    return q_ci + std::sqrt(fraction * elastic / 1e-18);
  }
} // namespace

TEST_CASE("crack volumetric strain: the onset of dilatancy, 2D and 3D, confined or not",
          "[labtests][crack_initiation]")
{
  // The fit window (10-30 % of the peak) lies below the onset (40 MPa), so
  // the crack volumetric strain is exactly zero there; the returned row is
  // the first whose dilatancy exceeds 5 % of the elastic volumetric strain
  // at the peak (2D: 1.5e-3, so 40 + 8.66 = 48.66 MPa, the row at 48.7 MPa;
  // 3D: 1e-3, 47.07 MPa). Exact to the row (0.1 MPa): the closed form of
  // the elastic part is what the method removes, in 2D (k = 1) and 3D
  // (k = 2), from any starting stress.
  for (int k : {1, 2})
    for (double sigma0 : {0.0, -10e6})
      {
        const auto        b = branch(k, sigma0, 40e6);
        const std::size_t row =
            crack_volumetric_initiation_row(b, E, nu, k, 0.1, 0.3, 0.05);
        INFO("k " << k << ", sigma0 " << sigma0 << ", row " << row);
        REQUIRE(row < b.load.size());
        CHECK(b.load[row] == Approx(std::ceil(expected(k, 40e6, 0.05) / 0.1e6) * 0.1e6));
        // A larger fraction moves it along the closed form.
        const std::size_t r20 =
            crack_volumetric_initiation_row(b, E, nu, k, 0.1, 0.3, 0.2);
        CHECK(b.load[r20] == Approx(std::ceil(expected(k, 40e6, 0.2) / 0.1e6) * 0.1e6));
      }
}

TEST_CASE("crack volumetric strain: noise and the wrong elasticity",
          "[labtests][crack_initiation]")
{
  // Noise of +-1 % of the elastic volumetric strain at the peak (the gauge
  // noise of the 1000-grain Lac du Bonnet specimen): the onset moves by
  // less than the band it can hide in, 40 + sqrt((0.05 -+ 0.01) 1.5e-3 /
  // 1e-18) MPa = 47.75 to 49.49 MPa.
  const auto        noisy = branch(1, 0, 40e6, 0.01);
  const std::size_t row =
      crack_volumetric_initiation_row(noisy, E, nu, 1, 0.1, 0.3, 0.05);
  REQUIRE(row < noisy.load.size());
  // The row returned is the one after the last row inside the band: up to
  // two rows (0.1 MPa each) beyond its upper end.
  CHECK(noisy.load[row] >= 47.75e6);
  CHECK(noisy.load[row] <= 49.49e6 + 0.2e6);
  // No dilatancy at all: not applicable (the number of rows).
  const auto elastic = branch(1, 0, 200e6);
  CHECK(crack_volumetric_initiation_row(elastic, E, nu, 1, 0.1, 0.3, 0.05) ==
        elastic.load.size());
  // No modulus, or no row in the window (rows are 0.001 of the peak apart):
  // not applicable.
  const auto b = branch(1, 0, 40e6);
  CHECK(crack_volumetric_initiation_row(b, 0, nu, 1, 0.1, 0.3, 0.05) == b.load.size());
  CHECK(crack_volumetric_initiation_row(b, E, nu, 1, 0.3002, 0.3008, 0.05) ==
        b.load.size());
  // A Poisson ratio 20 % too high (fitted over cracking) removes too little
  // volume: the crack volumetric strain then falls with load and its zero
  // shifts, so the onset comes later: the method is only as good as the
  // window's elasticity (docs/calibrate.md).
  const std::size_t high =
      crack_volumetric_initiation_row(b, E, 1.2 * nu, 1, 0.1, 0.3, 0.05);
  CHECK(b.load[high] > expected(1, 40e6, 0.05));
}

namespace
{
  /// Unconfined branch, 0.1 MPa per row up to 100 MPa (the peak): lateral
  /// strain nu q / E plus b (q - q_ci)^2 above q_ci; the volume (2D: axial
  /// plus lateral) shrinks elastically until the lateral dilatancy's rate
  /// 2 b (q - q_ci) outruns (1 - nu) / E: the reversal at
  /// q_cd = q_ci + (1 - nu) / (2 b E) = q_ci + 37.5 MPa for b = 2e-19 /Pa^2
  /// (dilatancy 7.2e-4 at the peak for q_ci = 40 MPa, against the elastic
  /// lateral strain's 5e-4).
  CompressionBranch lateral_branch(double q_ci, double noise = 0)
  {
    CompressionBranch                      b;
    const double                           c = 2e-19; // 1/Pa^2
    std::mt19937_64                        rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i <= 1000; ++i)
      {
        const double q   = 0.1e6 * i;
        const double ea  = -q / E;
        const double dil = q > q_ci ? c * (q - q_ci) * (q - q_ci) : 0;
        const double el  = 2e-4 + nu * q / E + dil + noise * nu * 100e6 / E * u(rng);
        b.axial_stress.push_back(-q);
        b.load.push_back(q);
        b.lateral_strain.push_back(el);
        b.volumetric_strain.push_back(ea + el);
      }
    b.peak_row = 1000;
    return b;
  }
} // namespace

TEST_CASE("lateral strain response: the farthest point from the line to crack damage",
          "[labtests][crack_initiation]")
{
  // Volumetric reversal (crack damage) where d(eps_v)/dq = 0:
  // -(1 - nu)/E + 2 b (q - q_ci) = 0, q_cd = 40 MPa + 0.75 / (4e-19 * 50e9)
  // = 77.5 MPa, row 775 (to the row: the rows on either side hold
  // b (0.1 MPa)^2 = 2e-9 more volume, far above rounding).
  const auto        b      = lateral_branch(40e6);
  const std::size_t damage = volumetric_reversal_row(b);
  REQUIRE(damage < b.load.size());
  CHECK(b.load[damage] == Approx(77.5e6));
  // The lateral strain's tangent slope nu/E + 2 b (q - q_ci) equals the
  // secant to crack damage, nu/E + b (q_cd - q_ci)^2 / q_cd, at
  // q = q_ci + (q_cd - q_ci)^2 / (2 q_cd) = 40 + 37.5^2 / 155 = 49.07 MPa:
  // the row at 49.1 MPa (exact: the distance below the line is a parabola
  // in q, 49.1 is its nearest row). The method reads after the true onset
  // (40 MPa) by (q_cd - q_ci)^2 / (2 q_cd), and without a threshold.
  const std::size_t ci = lateral_strain_initiation_row(b, damage);
  REQUIRE(ci < b.load.size());
  CHECK(b.load[ci] == Approx(49.1e6));
  // Linear in any starting offset of the strains: shifting the lateral
  // strain leaves the row unchanged.
  auto shifted = b;
  for (auto &e : shifted.lateral_strain)
    e += 1e-3;
  CHECK(lateral_strain_initiation_row(shifted, damage) == ci);

  // Noise of +-1 % of the elastic lateral strain at the peak (d = 5e-6) on
  // the same line: the distance below the line falls off as b (q - q*)^2
  // from its top, so noise can move the largest row only where
  // b (q - q*)^2 < 2 d: |q - q*| < sqrt(1e-5 / 2e-19) = 7.07 MPa. The
  // method's sensitivity: a flat top read on noisy gauges.
  const auto        noisy = lateral_branch(40e6, 0.01);
  const std::size_t nci   = lateral_strain_initiation_row(noisy, damage);
  REQUIRE(nci < noisy.load.size());
  CHECK(std::abs(noisy.load[nci] - 49.07e6) < 7.08e6);
}

TEST_CASE("lateral strain response and crack damage: where they do not apply",
          "[labtests][crack_initiation]")
{
  // Dilatancy starting at 95 MPa: the volume still shrinks at the peak
  // (q_cd would be 132.5 MPa): no crack damage, so no reference line.
  const auto late = lateral_branch(95e6);
  CHECK(volumetric_reversal_row(late) == late.load.size());
  CHECK(lateral_strain_initiation_row(late, late.load.size()) == late.load.size());
  // Damage row at the first row, past the peak, or no lateral rows.
  const auto b = lateral_branch(40e6);
  CHECK(lateral_strain_initiation_row(b, 0) == b.load.size());
  auto early_peak     = b;
  early_peak.peak_row = 500;
  CHECK(lateral_strain_initiation_row(early_peak, 775) == b.load.size());
  auto no_lateral = b;
  no_lateral.lateral_strain.clear();
  CHECK(lateral_strain_initiation_row(no_lateral, 775) == b.load.size());
  // A linear lateral strain (no dilatancy) lies on the line to any row
  // (to rounding): not applicable.
  auto linear = lateral_branch(200e6);
  CHECK(lateral_strain_initiation_row(linear, 775) == linear.load.size());
}
