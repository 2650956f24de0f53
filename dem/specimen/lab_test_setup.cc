// Setting up and seating each laboratory test (lab_test_runner.h):
// compression with its confining boundary (walls, flexible walls or the
// pressure boundary; fistPkg Table 10, docs/calibrate.md, "Confining
// boundary"), the Brazilian disk (§5.6, Table 11) and the direct-tension
// grips (§5.7, Table 12).
#include "dem/laws/linear_law.h"
#include "dem/specimen/lab_test_runner.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace demfem::dem::lab_detail
{
  // The confining servo of the seating (loading = false) or of the
  // loading phase; docs/calibrate.md, "What the tests do".
  template <int dim>
  ServoParams Runner<dim>::servo_params(double H, bool loading) const
  {
    ServoParams sp = p_.servo;
    // The seating's target does not move: proportional control settles
    // on it, and the integral term (for the loading's moving boundary)
    // stays out.
    if (!loading)
      sp.integral_gain = 0;
    // Given (Tests/servo velocity limit), it is the loading servo's;
    // the seating keeps the automatic bound below, which a larger given
    // limit would break (at 3 m/s a tiny specimen seated to 6 MPa failed
    // the energy check), and takes a smaller one.
    const double given = sp.v_limit;
    // A flexible wall's vertex without a contact closes at the seating's
    // speed: 10 eps_rate H, P_c / (rho c) at most (below).
    sp.v_free = 10 * p_.strain_rate * H;
    if (wave_speed() > 0 && p_.Pc > 0)
      sp.v_free = std::min(sp.v_free, p_.Pc / (s_.material.density * wave_speed()));
    if (loading && given > 0)
      return sp;
    sp.v_limit = 10 * p_.strain_rate * H; // Table 10 default: 10 eps_rate H
    if (!(wave_speed() > 0 && p_.Pc > 0))
      {
        if (given > 0)
          sp.v_limit = std::min(sp.v_limit, given);
        return sp;
      }
    // A wall moving at v sends a wave of rho c v into the specimen.
    // Seating from Pm to Pc faster than Pc / (rho c) overshoots Pc (at
    // 1/s, 10 eps_rate H seated a 250-grain specimen at 0.6 m/s against
    // 0.19 m/s and failed the energy check). In loading, a crack burst
    // unloads the surface by up to Pc, which at a free surface moves it
    // at 2 Pc / (rho c) (twice a wave's particle velocity): the walls
    // must be able to follow (10 eps_rate H held them back for thousands
    // of steps at 5-23 % above Pc in the 2D LdB triaxial tests).
    const double impedance = s_.material.density * wave_speed();
    sp.v_limit             = loading ? std::max(sp.v_limit, 2 * p_.Pc / impedance)
                                     : std::min(sp.v_limit, p_.Pc / impedance);
    if (given > 0)
      sp.v_limit = std::min(sp.v_limit, given);
    return sp;
  }

  template <int dim>
  void Runner<dim>::setup_compression()
  {
    const double H = s_.vessel.length(m_.walls, ax);
    r_.area        = s_.vessel.area(m_.walls, ax);
    // The pressure boundary (2D) replaces the lateral walls from the
    // seating on: the specimen settles under the boundary it is loaded
    // with (docs/calibrate.md, "Confining boundary").
    if constexpr (dim == 2)
      if (p_.pressure_boundary && p_.ctype == CompressionType::confined)
        {
          r_.confining_boundary = "pressure";
          pressure_boundary_    = std::make_unique<PressureBoundary>(p_.Pc);
        }
    if (p_.ctype == CompressionType::unconfined || pressure_boundary_)
      for (int a = 0; a < dim - 1; ++a)
        remove_walls(a);
    m_.reset_energy_baseline();
    if (p_.ctype == CompressionType::confined && p_.lateral_segments > 1)
      make_lateral_walls_flexible(H);
    if (p_.Pc > 0 || p_.ctype == CompressionType::confined)
      {
        // Seating: every wall present (unconfined, pressure boundary:
        // the platens only) servo-controlled to Pc, an isotropic start
        // for the confined and the uniaxial-strain tests.
        servo_ = std::make_unique<Servo<dim>>(s_.vessel, servo_params(H, false));
        for (int a = 0; a < dim; ++a)
          if (a == ax || (p_.ctype != CompressionType::unconfined && !pressure_boundary_))
            servo_->set_pressure(a, p_.Pc);
        if (pressure_boundary_) // the lateral walls are parked
          servo_->set_area(ax, r_.area);
        equilibrate(servo_.get());
      }
    else
      equilibrate(nullptr);
    L0_ = s_.vessel.length(m_.walls, ax);
    v_  = 0.5 * p_.strain_rate * L0_; // Table 10: v = eps_rate h / 2
    start_loading();
    s_.vessel.set_velocity(m_.walls, ax, -v_);
    if (pressure_boundary_) // it holds P_c on; the platens move
      servo_.reset();
    else if (servo_holds_confinement())
      {
        // Loading: the lateral walls stay on Pc while the specimen
        // dilates, with the integral term that removes the lag.
        r_.confining_boundary = s_.vessel.flexible(0) ? "flexible walls" : "rigid walls";
        const ServoParams sp  = servo_params(H, true);
        r_.confining_velocity_limit = sp.v_limit;
        r_.lateral_wall_segments    = s_.vessel.flexible(0) ? p_.lateral_segments : 1;
        servo_                      = std::make_unique<Servo<dim>>(s_.vessel, sp);
        for (int a = 0; a < dim - 1; ++a)
          servo_->set_pressure(a, p_.Pc);
        servo_->set_velocity(ax, -v_);
      }
    else
      servo_.reset(); // lateral walls fixed (uniaxial strain) or removed
  }

  // Flexible lateral walls before the seating, which settles the new
  // wall contacts; each facet at least two mean grain diameters long,
  // so that a vertex cannot wedge between two grains.
  template <int dim>
  void Runner<dim>::make_lateral_walls_flexible(double H)
  {
    double d = 0;
    for (std::size_t i = 0; i < m_.particles.size(); ++i)
      d += 2 * m_.particles.radius[i];
    d /= std::max<std::size_t>(1, m_.particles.size());
    const int n_max = std::max(1, static_cast<int>(H / (2 * d)));
    if (p_.lateral_segments > n_max)
      throw InputError(
          "lab test: lateral wall segments = " + std::to_string(p_.lateral_segments) +
          " makes facets of " + std::to_string(H / p_.lateral_segments) +
          " m, below two mean grain diameters (" + std::to_string(2 * d) +
          " m); allowed for this specimen: 1 to " + std::to_string(n_max));
    for (int a = 0; a < dim - 1; ++a)
      s_.vessel.make_flexible(m_.walls, a, p_.lateral_segments, far_);
  }

  // The lateral pressures (compression positive) of the confining walls
  // or of the pressure boundary (its two sides' mean).
  template <int dim>
  std::array<double, dim> Runner<dim>::lateral_pressures() const
  {
    std::array<double, dim> P{};
    for (int a = 0; a < dim - 1; ++a)
      P[a] =
          pressure_boundary_
              ? 0.5 * (pressure_boundary_->pressure(0) + pressure_boundary_->pressure(1))
              : servo_->pressure(m_, a);
    return P;
  }

  // P_c on the outermost grains between the platens (2D).
  template <int dim>
  void Runner<dim>::apply_pressure_boundary()
  {
    if constexpr (dim == 2)
      {
        const auto &W = m_.walls;
        pressure_boundary_->apply(m_.particles, W.vertex[s_.vessel.lo_vertex[ax]][ax],
                                  W.vertex[s_.vessel.hi_vertex[ax]][ax]);
      }
  }

  template <int dim>
  typename Runner<dim>::ConfinementGauge Runner<dim>::confinement_gauge() const
  {
    ConfinementGauge g;
    g.Pc        = p_.Pc;
    g.n_lateral = s_.vessel.cylinder() ? 1 : dim - 1; // the cylinder's wall: axis 0
    double W    = HUGE_VAL;
    for (int a = 0; a < dim - 1; ++a)
      W = std::min(W, s_.vessel.length(m_.walls, a));
    if (pressure_boundary_) // the walls are parked: the seated width (2D)
      W = r_.area;
    g.window = wave_speed() > 0 ? W / wave_speed() : 0;
    return g;
  }

  template <int dim>
  void Runner<dim>::setup_brazilian()
  {
    // Carve the disk (2D) or the cylinder with its axis along y (3D) of
    // radius R = min(W, H)/2 centred on the vessel (§5.6, Fig. 29); a
    // flattened disk also loses the grains beyond the flats
    // |x_ax| = R cos alpha (LabTestParams::brazilian_flat_angle).
    const Vec<dim> c = s_.vessel.center;
    const double   R =
        0.5 * std::min(s_.vessel.length(m_.walls, 0), s_.vessel.length(m_.walls, ax));
    const double cos_alpha = std::cos(0.5 * p_.brazilian_flat_angle * M_PI / 180);
    r_.t                   = dim == 2 ? 1.0 : s_.vessel.length(m_.walls, 1);
    std::vector<char> remove(m_.particles.size(), 0);
    for (std::size_t i = 0; i < m_.particles.size(); ++i)
      {
        Vec<dim> d = m_.particles.x[i] - c;
        if (dim == 3)
          d[1] = 0;
        const double r = m_.particles.radius[i];
        remove[i]      = d.norm() + r > R || std::abs(d[ax]) + r > R * cos_alpha;
      }
    m_.remove_particles(remove);
    for (int a = 0; a < dim - 1; ++a)
      remove_walls(a);
    // Platens (the axial walls) touch the disk: frictionless (the grain-
    // wall group), stiffness from the vessel's effective modulus.
    double top = -HUGE_VAL, bottom = HUGE_VAL;
    for (std::size_t i = 0; i < m_.particles.size(); ++i)
      {
        top    = std::max(top, m_.particles.x[i][ax] + m_.particles.radius[i]);
        bottom = std::min(bottom, m_.particles.x[i][ax] - m_.particles.radius[i]);
      }
    // The platens are symmetric about the vessel centre: centre the disk
    // between them (a rigid shift), then close them onto it.
    const double shift = c[ax] - 0.5 * (top + bottom);
    for (std::size_t i = 0; i < m_.particles.size(); ++i)
      m_.particles.x[i][ax] += shift;
    const double L = s_.vessel.length(m_.walls, ax);
    s_.vessel.translate_outward(m_.walls, ax, 0.5 * ((top - bottom) - L));
    // The disk's radius from the platen gap: the platens stand
    // 2 R cos alpha apart (round disk: 2 R).
    r_.R = 0.5 * (top - bottom) / cos_alpha;
    if (p_.platen_friction > 0)
      platen_friction();
    m_.invalidate_contacts();
    m_.reset_energy_baseline();
    seat_brazilian();
    equilibrate(nullptr);
    L0_ = s_.vessel.length(m_.walls, ax);
    v_  = 0.5 * p_.strain_rate * L0_; // Table 11: v = eps_rate g0 / 2
    start_loading();
    s_.vessel.set_velocity(m_.walls, ax, -v_);
  }

  // Seating of the Brazilian disk: the platens first touch one or two
  // grains each, and a coarse 3D cylinder rocks about its axis on them
  // (measured: 3000 grains, ~11 across, peak 0.11 MPa while the disk
  // rotated, ended by the load-fraction rule). The platens close at the
  // loading speed until the Eq. 22 load reaches F = P_m pi R t (the
  // material pressure: the packing stress, low relative to the
  // strength, fistPkg §4.2.1) or the loading step limit, then stop; the disk
  // settles on a stable seat before loading starts.
  template <int dim>
  void Runner<dim>::seat_brazilian()
  {
    const double Fseat = s_.material.Pm * M_PI * r_.R * r_.t;
    if (!(Fseat > 0))
      return;
    const auto  &W    = m_.walls;
    const double gap0 = s_.vessel.length(W, ax);
    const double vs   = 0.5 * p_.strain_rate * gap0;
    s_.vessel.set_velocity(m_.walls, ax, -vs);
    for (std::int64_t n = 0; n < p_.step_limit; ++n)
      {
        m_.step();
        const double F = -0.5 * (W.wall_force(s_.vessel.lo[ax])[ax] -
                                 W.wall_force(s_.vessel.hi[ax])[ax]);
        if (F >= Fseat)
          break;
        // A soft disk can close the platens for minutes before it carries
        // the seating load (3D: 0.4 % platen travel, about 225 000 steps):
        // say so. Stress: the load as the material pressure it is compared
        // with; fraction: of the step limit, as in equilibrate().
        if (cb_.progress && n % 100 == 99)
          {
            LabProgress g;
            g.phase         = "seating";
            g.step          = n + 1;
            g.stress        = F / (M_PI * r_.R * r_.t);
            g.strain        = (s_.vessel.length(W, ax) - gap0) / gap0;
            g.fraction_done = double(n + 1) / p_.step_limit;
            cb_.progress(g);
          }
      }
    s_.vessel.set_velocity(m_.walls, ax, 0);
  }

  // Grain-platen contacts: the grain-wall linear law with friction.
  template <int dim>
  void Runner<dim>::platen_friction()
  {
    using Group    = ContactGroup<dim, LinearLaw<dim>>;
    const auto *wg = dynamic_cast<const Group *>(&m_.group(s_.wall_group));
    if (!wg)
      throw InputError("lab test: platen friction needs a linear grain-wall law");
    // The grain-wall group is frictionless with ks = 0 (§4.1): without a
    // shear stiffness no shear force ever builds and the friction
    // coefficient does nothing (a coarse 3D disk rotated between the
    // platens and carried no load). The platen contacts keep the
    // grain-wall kn of each contact, with the shear stiffness of the
    // material's linear group, ks = kn / kappa*, and the platen friction.
    const double         krat     = s_.material.lnm_krat > 0 ? s_.material.lnm_krat : 1.0;
    const double         friction = p_.platen_friction;
    typename Group::Rule wall_rule     = wg->rule;
    typename LinearLaw<dim>::Params lp = wg->params;
    lp.friction                        = friction;
    lp.ks                              = lp.kn / krat;
    const int g                        = m_.template add_law<LinearLaw<dim>>(
        lp, "platen friction",
        [wall_rule, krat, friction](const ContactGeometry<dim>     &geo,
                                    typename LinearLaw<dim>::Props &q) {
          if (wall_rule)
            wall_rule(geo, q);
          q.ks       = q.kn / krat;
          q.friction = friction;
        });
    std::vector<ContactRef> walls;
    for (int k = 0; k < m_.n_groups(); ++k)
      for (std::size_t c = 0; c < m_.group(k).size(); ++c)
        if (m_.group(k).is_wall[c])
          walls.push_back({k, c});
    // Reassign from the back so the indices of the rest stay valid.
    for (auto it = walls.rbegin(); it != walls.rend(); ++it)
      m_.reassign(*it, g);
    m_.set_default_law(s_.linear_group, g);
  }

  template <int dim>
  void Runner<dim>::setup_tension()
  {
    r_.area = s_.vessel.area(m_.walls, ax);
    for (int a = 0; a < dim; ++a)
      remove_walls(a);
    double top = -HUGE_VAL, bottom = HUGE_VAL;
    for (std::size_t i = 0; i < m_.particles.size(); ++i)
      {
        top    = std::max(top, m_.particles.x[i][ax] + m_.particles.radius[i]);
        bottom = std::min(bottom, m_.particles.x[i][ax] - m_.particles.radius[i]);
      }
    const double H  = top - bottom;
    const double tg = p_.grip_thickness * H; // Table 12: t_g
    for (std::uint32_t i = 0; i < m_.particles.size(); ++i)
      if (m_.particles.x[i][ax] > top - tg)
        grip_top_.push_back(i);
      else if (m_.particles.x[i][ax] < bottom + tg)
        grip_bottom_.push_back(i);
    m_.reset_energy_baseline();
    equilibrate(nullptr);
    // Grip centres' distance is the gauge length of the platen strain.
    L0_ = H - tg;
    v_  = 0.5 * p_.strain_rate * L0_;
    start_loading();
    // Grip grains neither translate nor spin except the axial pull
    // (glued to rigid platens, §5.7).
    for (auto i : grip_top_)
      hold(i, +v_);
    for (auto i : grip_bottom_)
      hold(i, -v_);
    m_.reset_energy_baseline();
  }

  template class Runner<2>;
  template class Runner<3>;
} // namespace demfem::dem::lab_detail
