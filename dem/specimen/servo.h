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
    /// Integral gain beta of the per-axis control (0: proportional only).
    /// A proportional servo lags a boundary that must keep moving (a
    /// specimen dilating under the platens) by e = v / G; the integral term
    /// learns that velocity and removes the lag:
    /// v = G (e + (beta / alpha) sum of e over the steps), i.e. an integral
    /// time T_i = alpha dt / beta. Like alpha it is a per-step gain (G is
    /// per step, fistPkg Table 9). Allowed 0 <= beta <= 2 - alpha -
    /// 2 sqrt(1 - alpha): the loop of one wall on grains that stay put,
    /// e_{n+1} = (1 - alpha) e_n - beta sum e, then has real poles and does
    /// not overshoot (alpha 0.5, beta 0.05: poles 0.89 and 0.56). A wall
    /// pair moves both walls for the mean pressure and closes half of that
    /// (poles 0.86 +- 0.08i: damped). docs/calibrate.md, "What the tests do".
    double integral_gain = 0.05;
    /// Flexible walls: speed [m/s] at which a vertex between the platens
    /// without a contact closes on the specimen (0: v_limit). A membrane
    /// under pressure closes on a void; at a large v_limit (40 m/s) a
    /// vertex driven in at the limit wedged grains between two facets and
    /// broke the energy balance (docs/calibrate.md, "Confining servo").
    double v_free = 0;
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
    void update(Model<dim> &m);
    /// Wall pressure (compression positive) of axis a.
    double pressure(const Model<dim> &m, int a) const;
    /// The area axis a's walls press on, instead of the vessel's current
    /// one (> 0; 2D planar walls): the platens of a specimen whose lateral
    /// walls were parked (a pressure boundary) press on the specimen's
    /// width, not on the parked walls' distance.
    void set_area(int a, double A) { area_[a] = A; }
    /// All servo-controlled pressures within tol of their targets.
    bool within_tolerance(const Model<dim> &m) const;
    void stop(Model<dim> &m); ///< zero wall velocities and the integral term
    /// A new velocity limit (> 0) for the next updates [m/s].
    void   set_velocity_limit(double v_limit) { p_.v_limit = v_limit; }
    double velocity_limit() const { return p_.v_limit; }

  private:
    /// Flexible walls of lateral axis a: each vertex closes alpha of its own
    /// pressure error per step (docs/calibrate.md, "Confining servo").
    void update_flexible(Model<dim> &m, int a, double dt);
    /// Proportional velocity v plus the integral term, whose running sum
    /// `integral` it updates (beta / alpha of v per step).
    double with_integral(double v, double &integral) const;

    Vessel<dim>             vessel_; // a copy: ids only, positions live in the walls
    ServoParams             p_;
    std::array<bool, dim>   on_;
    std::array<double, dim> target_, velocity_;
    std::array<double, dim> integral_velocity_; // G / T_i int e dt, per axis
    std::array<double, dim> area_;              // set_area (0: the vessel's)
    double                  area(const Model<dim> &m, int a) const;
    // Flexible walls: per wall vertex, the summed stiffness of its contacts
    // (each weighted by the vertex's barycentric weight) and the integral
    // velocity; indexed by wall vertex.
    std::vector<double> vertex_kn_, vertex_integral_;
  };
} // namespace demfem::dem
