// Pressure boundary of a 2D compression specimen (pressure_boundary.h).
#include "dem/specimen/pressure_boundary.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace demfem::dem
{
  PressureBoundary::PressureBoundary(double P)
      : P_(P)
  {
    check_range("pressure boundary", "confining pressure", P, 0, HUGE_VAL);
  }

  void PressureBoundary::remove(Particles<2> &p)
  {
    for (std::size_t j = 0; j < loaded_.size(); ++j)
      p.f_ext[loaded_[j]] -= applied_[j];
    loaded_.clear();
    applied_.clear();
  }

  void PressureBoundary::cast_rays(const Particles<2> &p, double y_lo, double y_hi, int s)
  {
    // Rays a quarter of the smallest radius apart: a grain exposed over
    // more than that height is on at least one ray. Their heights move with
    // the platens (the same count between them at every step).
    if (!(r_min_ > 0))
      r_min_ = p.min_radius();
    const double gap = y_hi - y_lo;
    const auto   n =
        static_cast<std::size_t>(std::max(1.0, std::ceil(gap / (0.25 * r_min_))));
    const double h       = gap / double(n);
    const double outward = s ? 1.0 : -1.0;
    // Grain i's surface outward of each ray k it crosses (|y_k - y_i| < r,
    // y_k = y_lo + (k + 1/2) h); keeps the farthest.
    const auto visit = [&](std::size_t i, std::vector<double> &reach,
                           std::vector<std::int64_t> *owner) {
      const double r    = p.radius[i];
      const double yi   = p.x[i][1];
      const double k_lo = std::max(0.0, std::ceil((yi - r - y_lo) / h - 0.5));
      const double k_hi = std::min(double(n - 1), std::floor((yi + r - y_lo) / h - 0.5));
      for (double kk = k_lo; kk <= k_hi; ++kk)
        {
          const auto   k  = static_cast<std::size_t>(kk);
          const double dy = y_lo + (kk + 0.5) * h - yi;
          const double d2 = r * r - dy * dy;
          if (!(d2 > 0))
            continue;
          const double out = outward * p.x[i][0] + std::sqrt(d2);
          if (out > reach[k])
            {
              reach[k] = out;
              if (owner)
                (*owner)[k] = static_cast<std::int64_t>(i);
            }
        }
    };
    // The last chain's grains, where they are now, reach at least so far
    // on every ray they cross (any grain's reach is a lower bound of a
    // ray's farthest): a grain whose outermost point x +- r lies inside the
    // smallest of these bounds is outermost on no ray. The scan below skips
    // it and finds exactly what a full scan finds, at a few layers of
    // grains' cost.
    double inside = -HUGE_VAL;
    if (!chain_[s].empty())
      {
        reach_.assign(n, -HUGE_VAL);
        for (auto i : chain_[s])
          if (i < p.size())
            visit(i, reach_, nullptr);
        inside = *std::min_element(reach_.begin(), reach_.end());
      }
    reach_.assign(n, -HUGE_VAL);
    owner_.assign(n, -1);
    for (std::size_t i = 0; i < p.size(); ++i)
      if (!(outward * p.x[i][0] + p.radius[i] < inside))
        visit(i, reach_, &owner_);
    auto &chain = chain_[s];
    chain.clear();
    for (auto o : owner_)
      if (o >= 0 && (chain.empty() || chain.back() != std::uint32_t(o)))
        chain.push_back(static_cast<std::uint32_t>(o));
  }

  void PressureBoundary::apply(Particles<2> &p, double y_lo, double y_hi)
  {
    if (!(y_hi > y_lo))
      throw InputError("pressure boundary: the platens crossed (gap " +
                       std::to_string(y_hi - y_lo) + " m)");
    remove(p);
    for (int s = 0; s < 2; ++s)
      {
        cast_rays(p, y_lo, y_hi, s);
        const auto  &chain   = chain_[s];
        const double outward = s ? 1.0 : -1.0;
        double       Fx      = 0;
        const auto   push    = [&](std::uint32_t i, const Vec<2> &F) {
          loaded_.push_back(i);
          applied_.push_back(F);
          p.f_ext[i] += F;
          Fx += F[0];
        };
        if (chain.empty())
          {
            pressure_[s] = 0;
            continue;
          }
        // The pieces between the platens and the end centres: horizontal.
        const Vec<2> &first = p.x[chain.front()], &last = p.x[chain.back()];
        push(chain.front(), Vec<2>(-outward * P_ * (first[1] - y_lo), 0));
        push(chain.back(), Vec<2>(-outward * P_ * (y_hi - last[1]), 0));
        // Each segment d (upward along the side) has the outward normal
        // times its length outward (d_y, -d_x); P_c on it, inward, half
        // on each end.
        for (std::size_t j = 0; j + 1 < chain.size(); ++j)
          {
            const Vec<2> d = p.x[chain[j + 1]] - p.x[chain[j]];
            const Vec<2> F = -0.5 * outward * P_ * Vec<2>(d[1], -d[0]);
            push(chain[j], F);
            push(chain[j + 1], F);
          }
        pressure_[s] = -outward * Fx / (y_hi - y_lo);
      }
  }
} // namespace demfem::dem
