#pragma once
// A pressure boundary on the lateral sides of a 2D compression specimen: the
// confining pressure P_c as forces on the outermost grains themselves, the
// membrane of a triaxial cell without stiffness (docs/calibrate.md,
// "Confining boundary"). Each step, each side's outermost grains between
// the platens are found by casting horizontal rays at heights spaced a
// quarter of the smallest radius apart (the grain reaching farthest out on
// a ray is on the boundary there); ordered by height their centres form a
// polygon, and each polygon segment carries P_c times its length along its
// inward normal, half on each end grain; the pieces between the platens and
// the first and last centres carry P_c horizontally. So each side's force
// is exactly P_c times the platen gap (unit depth), whatever the shape of
// the boundary, and a grain a crack burst throws outward is pushed back by
// its share of P_c instead of kicking a servo-controlled wall.
#include "dem/engine/particles.h"

#include <array>
#include <cstdint>
#include <vector>

namespace demfem::dem
{
  class PressureBoundary
  {
  public:
    /// P: the confining pressure (compression positive, >= 0) [Pa].
    explicit PressureBoundary(double P);

    /// Finds both sides' outermost grains between the platens at heights
    /// y_lo < y_hi and sets their external forces (the previous step's
    /// contributions are taken back first, so other external forces stay).
    void apply(Particles<2> &p, double y_lo, double y_hi);
    /// Takes every applied force back.
    void remove(Particles<2> &p);

    /// The pressure the applied forces exert on side s (0: -x, 1: +x): their
    /// horizontal sum over the platen gap (P to round-off; a check).
    double pressure(int side) const { return pressure_[side]; }
    /// The grains each side's forces act on, ordered by height.
    const std::vector<std::uint32_t> &chain(int side) const { return chain_[side]; }

  private:
    /// Outermost grain of each ray on side s (outward = -1: -x, +1: +x).
    void cast_rays(const Particles<2> &p, double y_lo, double y_hi, int s);

    double P_;
    double r_min_ = 0; // smallest radius (rays' spacing)
    std::array<std::vector<std::uint32_t>, 2> chain_;
    std::vector<double>                       reach_;   // per ray: outermost surface
    std::vector<std::int64_t>                 owner_;   // per ray: its grain (-1: none)
    std::vector<std::uint32_t>                loaded_;  // grains with a force applied
    std::vector<Vec<2>>                       applied_; // their forces
    std::array<double, 2>                     pressure_{};
  };
} // namespace demfem::dem
