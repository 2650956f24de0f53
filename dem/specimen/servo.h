#pragma once
// Servomechanism on the vessel walls (fistPkg §5.3, Table 9; Itasca 2008
// §3.10.5): v = G (sigma_target - sigma_wall) with G = alpha A / (k_n dt),
// k_n the summed normal stiffness of the contacts on the wall, velocity
// limited to v_limit. Compression positive in the targets (pressures).
#include "dem/engine/model.h"
#include "dem/specimen/vessel.h"

namespace demfem::dem
{
  struct ServoParams
  {
    double alpha   = 0.5;  ///< gain factor (Table 9, alpha in (0, 1))
    double v_limit = 0;    ///< velocity limit [m/s] (> 0)
    double tol     = 1e-2; ///< equilibrium-pressure tolerance eps_P
    /// One velocity for all pressure-controlled axes from their mean
    /// pressure (isotropic compression, used for packing): per-axis control
    /// stalls when the assembly carries a deviator at yield.
    bool isotropic = false;
  };

  template <int dim>
  class Servo
  {
  public:
    Servo(const Vessel<dim> &vessel, const ServoParams &p);
    /// Target pressure (compression positive) of axis a; on[a] = false gives a
    /// velocity boundary condition (set by set_velocity).
    void set_pressure(int a, double P);
    void set_velocity(int a, double v);
    /// Sets the wall velocities from the current wall pressures; call every
    /// step before Model::step.
    void update(Model<dim> &m) const;
    /// Wall pressure (compression positive) of axis a.
    double pressure(const Model<dim> &m, int a) const;
    /// All servo-controlled pressures within tol of their targets.
    bool within_tolerance(const Model<dim> &m) const;
    void stop(Model<dim> &m) const; ///< zero wall velocities

  private:
    Vessel<dim>             vessel_; // a copy: ids only, positions live in the walls
    ServoParams             p_;
    std::array<bool, dim>   on_;
    std::array<double, dim> target_, velocity_;
  };
} // namespace demfem::dem
