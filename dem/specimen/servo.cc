// Servomechanism on the vessel walls (fistPkg §5.3, Table 9).
#include "dem/specimen/servo.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem
{
  template <int dim>
  Servo<dim>::Servo(const Vessel<dim> &vessel, const ServoParams &p)
      : vessel_(vessel)
      , p_(p)
  {
    check_range("servo", "alpha", p.alpha, 0, 1, true, true);
    check_range("servo", "v_limit", p.v_limit, 0, HUGE_VAL, true);
    check_range("servo", "tol", p.tol, 0, 1, true, true);
    check_range("servo", "integral gain", p.integral_gain, 0,
                2 - p.alpha - 2 * std::sqrt(1 - p.alpha));
    on_.fill(false);
    target_.fill(0);
    velocity_.fill(0);
    integral_velocity_.fill(0);
    area_.fill(0);
  }

  template <int dim>
  void Servo<dim>::set_pressure(int a, double P)
  {
    on_[a]     = true;
    target_[a] = P;
    // The cylinder's lateral axes share one wall: keep them consistent.
    if (vessel_.cylinder() && a < dim - 1)
      for (int b = 0; b < dim - 1; ++b)
        {
          on_[b]     = true;
          target_[b] = P;
        }
  }

  template <int dim>
  void Servo<dim>::set_velocity(int a, double v)
  {
    on_[a]       = false;
    velocity_[a] = v;
    if (vessel_.cylinder() && a < dim - 1)
      for (int b = 0; b < dim - 1; ++b)
        {
          on_[b]       = false;
          velocity_[b] = v;
        }
  }

  template <int dim>
  double Servo<dim>::pressure(const Model<dim> &m, int a) const
  {
    if (area_[a] > 0) // the walls' mean force over the given area
      {
        const auto &W = m.walls;
        return 0.5 * (W.wall_force(vessel_.hi[a])[a] - W.wall_force(vessel_.lo[a])[a]) /
               area_[a];
      }
    return -vessel_.wall_stress(m.walls, a);
  }

  template <int dim>
  double Servo<dim>::area(const Model<dim> &m, int a) const
  {
    return area_[a] > 0 ? area_[a] : vessel_.area(m.walls, a);
  }

  template <int dim>
  void Servo<dim>::update(Model<dim> &m)
  {
    // Summed normal stiffness of the contacts on each wall pair (Itasca
    // 2008 §3.10.5: G = alpha A / (k_n N_c dt)).
    std::array<double, dim> kn;
    kn.fill(0);
    bool any_flexible = false;
    for (int a = 0; a < dim; ++a)
      any_flexible = any_flexible || vessel_.flexible(a);
    if (any_flexible)
      vertex_kn_.assign(m.walls.vertex.size(), 0.0);
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          {
            if (!grp.is_wall[k] || !grp.active(k))
              continue;
            const int wall = m.walls.facet_wall[grp.end2[k]];
            for (int a = 0; a < dim; ++a)
              if (wall == vessel_.lo[a] || wall == vessel_.hi[a] ||
                  (a == 0 && wall == vessel_.side))
                {
                  const double k_n = grp.stiffness(k, m.particles).kn;
                  kn[a] += k_n;
                  if (vessel_.flexible(a))
                    for (int j = 0; j < dim; ++j)
                      vertex_kn_[m.walls.facet[grp.end2[k]][j]] +=
                          grp.facet_weights[k][j] * k_n;
                }
          }
      }
    double dt = m.timestep();
    if (dt <= 0)
      dt = m.safety_factor * m.critical_timestep();
    // Isotropic mode: moving every wall by dx changes the mean pressure by
    // dx (1/n) sum k_a / A_a; close alpha of the mean error per step.
    double v_iso = 0;
    if (p_.isotropic && dt > 0)
      {
        double err = 0, k = 0;
        int    n = 0;
        for (int a = 0; a < dim; ++a)
          if (on_[a])
            {
              err += pressure(m, a) - target_[a];
              k += kn[a] / area(m, a);
              ++n;
            }
        if (n > 0)
          v_iso = k > 0 ? p_.alpha * (err / n) / (k / n * dt)
                        : (err > 0 ? p_.v_limit : -p_.v_limit);
        v_iso = std::clamp(v_iso, -p_.v_limit, p_.v_limit);
      }
    for (int a = 0; a < dim; ++a)
      {
        if (vessel_.cylinder() && a > 0 && a < dim - 1)
          continue; // lateral axes share the cylinder wall (handled by a = 0)
        double v = velocity_[a];
        if (on_[a] && p_.isotropic)
          {
            vessel_.set_velocity(m.walls, a, v_iso);
            continue;
          }
        if (on_[a] && vessel_.flexible(a))
          {
            update_flexible(m, a, dt);
            continue;
          }
        if (on_[a])
          {
            const double err = pressure(m, a) - target_[a]; // > 0: too much, open
            if (kn[a] > 0 && dt > 0)
              {
                // Each wall of a pair moves by v: the pair's stiffness halves.
                const double G = p_.alpha * area(m, a) / (kn[a] * dt);
                v              = with_integral(G * err, integral_velocity_[a]);
              }
            else
              v = err > 0 ? p_.v_limit : -p_.v_limit;
            v = std::clamp(v, -p_.v_limit, p_.v_limit);
          }
        vessel_.set_velocity(m.walls, a, v);
      }
  }

  template <int dim>
  double Servo<dim>::with_integral(double v, double &integral) const
  {
    if (!(p_.integral_gain > 0))
      return v;
    // Conditional integration (anti-windup): the integral stops growing
    // while the velocity limit holds the wall.
    const double vi = integral + (p_.integral_gain / p_.alpha) * v;
    if (std::abs(v + vi) < p_.v_limit)
      integral = vi;
    return v + integral;
  }

  template <int dim>
  void Servo<dim>::update_flexible(Model<dim> &m, int a, double dt)
  {
    // A vertex moved by dx changes the force on itself by about
    // sum w k_n dx over the contacts of its facets (w its barycentric
    // weight: all vertices of the wall moving together, the stiffer of the
    // wall's modes, so alpha stays a stable per-step gain), and its
    // pressure by that over its tributary area A (the platen gap's share it
    // carries): v = alpha A e / (k dt), e its pressure above the target.
    // Vertices beyond the platens carry nothing and follow their nearest
    // loaded neighbour, so the facets there extend the membrane. A vertex
    // between the platens without a contact closes on the specimen at
    // v_free: following its neighbours instead, the vertices a burst
    // pushed off the specimen stayed off and the wall held 8 % below P_c
    // for hundreds of steps (2D LdB, 16 facets).
    vertex_integral_.resize(m.walls.vertex.size(), 0.0);
    auto &W = m.walls;
    for (int s = 0; s < 2; ++s)
      {
        const auto  &chain   = s ? vessel_.hi_chain[a] : vessel_.lo_chain[a];
        const double outward = s ? 1.0 : -1.0;
        const auto   A       = vessel_.tributary_areas(W, chain);
        // A vertex whose hat lies almost wholly beyond a platen is unloaded.
        double A_max = 0;
        for (double Ak : A)
          A_max = std::max(A_max, Ak);
        // The vertices between the platens are a contiguous run
        // [first, last] of the chain.
        std::size_t first = chain.size(), last = 0;
        for (std::size_t k = 0; k < chain.size(); ++k)
          {
            const int v = chain[k];
            if (!(A[k] > 1e-3 * A_max))
              continue;
            first                = std::min(first, k);
            last                 = k;
            W.vertex_velocity[v] = Vec<dim>::Zero();
            if (!(vertex_kn_[v] > 0 && dt > 0))
              {
                const double v_free =
                    p_.v_free > 0 ? std::min(p_.v_free, p_.v_limit) : p_.v_limit;
                W.vertex_velocity[v][a] = -outward * v_free;
                continue;
              }
            const double P   = outward * W.vertex_force[v][a] / A[k];
            const double err = P - target_[a]; // > 0: too much, open
            const double vel =
                std::clamp(with_integral(p_.alpha * A[k] * err / (vertex_kn_[v] * dt),
                                         vertex_integral_[v]),
                           -p_.v_limit, p_.v_limit);
            W.vertex_velocity[v][a] = outward * vel;
          }
        if (first == chain.size()) // the platens closed past every vertex
          {
            for (int v : chain)
              W.vertex_velocity[v] = Vec<dim>::Zero();
            continue;
          }
        // Vertices beyond the platens: the velocity of the nearest one
        // between them.
        for (std::size_t k = 0; k < first; ++k)
          W.vertex_velocity[chain[k]] = W.vertex_velocity[chain[first]];
        for (std::size_t k = last + 1; k < chain.size(); ++k)
          W.vertex_velocity[chain[k]] = W.vertex_velocity[chain[last]];
      }
  }

  template <int dim>
  bool Servo<dim>::within_tolerance(const Model<dim> &m) const
  {
    for (int a = 0; a < dim; ++a)
      if (on_[a] && std::abs(pressure(m, a) - target_[a]) > p_.tol * std::abs(target_[a]))
        return false;
    return true;
  }

  template <int dim>
  void Servo<dim>::stop(Model<dim> &m)
  {
    integral_velocity_.fill(0);
    vertex_integral_.assign(vertex_integral_.size(), 0.0);
    for (int a = 0; a < dim; ++a)
      if (!(vessel_.cylinder() && a > 0 && a < dim - 1))
        vessel_.set_velocity(m.walls, a, 0.0);
  }

  template class Servo<2>;
  template class Servo<3>;
} // namespace demfem::dem
