#pragma once
// One instability monitor for the DEM engine, the continuum and the coupled
// model (docs/architecture.md, "Instability monitoring"): a quantity that
// an unstable explicit integration amplifies by a constant factor per step
// (kinetic energy, an interface residual) is fed step by step; a streak of
// growth beyond the rule's factor, or a non-finite value, is an
// instability. The rules — thresholds named and justified here, once — are
// below. Header-only, standard C++ only, so that dem/, fem/ and coupling/
// all use it.
#include <array>
#include <cmath>
#include <stdexcept>

namespace demfem::instability
{
  struct GrowthRule
  {
    double factor; ///< growth counts when value > factor x previous value
    int    steps;  ///< consecutive growth steps that make an instability (<= 15)
    /// Growth from a previous value of zero counts (a start from rest).
    bool from_zero;
    /// Tell an unstable integration (constant ratio per step) from a start
    /// from rest driven as a power of time, t^k, whose ratio per step
    /// (1 + 1/n)^k falls steadily: unstable only when the last five of the
    /// streak's log-ratios add up to at least half of the first five.
    bool constant_ratio_only;
  };

  /// DEM kinetic energy, checked every step. An unstable central-difference
  /// integration multiplies the energy by (much) more than 1.5 per step, a
  /// damped loading far less; 15 steps rule out a few steps of impact. A
  /// load applied a few elements from free grains (a 3D section's tunnel-
  /// wall traction, ramped from rest) drives them as t^8 or so: ratios 8.9,
  /// 4.0, 2.7, ... still above 1.5 after 15 steps (measured), yet the last
  /// five log-ratios average 0.2-0.35 times the first five: hence
  /// constant_ratio_only.
  inline constexpr GrowthRule dem_kinetic_energy{1.5, 15, true, true};
  /// The continuum's kinetic energy, checked every continuum step (same
  /// factor and streak as the DEM).
  inline constexpr GrowthRule continuum_kinetic_energy{1.5, 15, true, false};
  /// The quasi-static coupling's interface residual |u* - u| / |u*|, checked
  /// every window: a converging relaxation shrinks it, a diverging one
  /// (relaxation too large for the stiffness contrast) grows it by a
  /// constant factor; 20 % per window for 15 windows is far from the
  /// oscillation of a converging one.
  inline constexpr GrowthRule interface_residual{1.2, 15, false, false};

  /// Kinetic + strain energy may not exceed this factor times the initial
  /// energy plus the external work (damping and slip only remove energy;
  /// the central-difference round-off of the balance is O((w dt)^2), below
  /// 100 % under the critical step).
  inline constexpr double energy_balance_factor = 2.0;

  class GrowthMonitor
  {
  public:
    explicit GrowthMonitor(const GrowthRule &rule)
        : rule_(rule)
    {
      if (rule.steps < 5 || rule.steps > int(log_ratios_.size()) || !(rule.factor > 1))
        throw std::invalid_argument("GrowthMonitor: steps in [5, 15], factor > 1");
    }

    /// Feeds the next value; true when it shows an instability (growth over
    /// the rule's streak, or a non-finite value). Values at or below `floor`
    /// (a round-off level) never count as growth.
    bool update(double value, double floor = 0)
    {
      if (!std::isfinite(value))
        return true;
      const bool grew =
          value > rule_.factor * last && value > floor && (rule_.from_zero || last > 0);
      streak = grew ? streak + 1 : 0;
      if (grew && rule_.constant_ratio_only)
        log_ratios_[n_logged_++ % log_ratios_.size()] = std::log(value / last);
      else if (!grew)
        n_logged_ = 0;
      last = value;
      if (streak < rule_.steps)
        return false;
      if (!rule_.constant_ratio_only)
        return true;
      // After a restart in mid-streak the ratios of the streak are not in
      // the checkpoint: detection waits for a full streak of new ones.
      if (n_logged_ < rule_.steps)
        return false;
      const int m     = int(log_ratios_.size());
      double    first = 0, latest = 0;
      for (int k = 0; k < 5; ++k)
        {
          first += log_ratios_[(n_logged_ - rule_.steps + k) % m];
          latest += log_ratios_[(n_logged_ - 5 + k) % m];
        }
      return latest >= 0.5 * first;
    }

    /// The previous value and the current growth streak (checkpointed).
    double last   = 0;
    int    streak = 0;

  private:
    GrowthRule             rule_;
    std::array<double, 15> log_ratios_{};
    int                    n_logged_ = 0;
  };
} // namespace demfem::instability
