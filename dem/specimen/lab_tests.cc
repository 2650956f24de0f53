// Laboratory tests and property extraction (see lab_tests.h; fistPkg
// §5.2, §5.4-5.7).
#include "dem/specimen/lab_tests.h"

#include "dem/specimen/brazilian_failure.h"
#include "dem/specimen/crack_initiation.h"
#include "dem/specimen/post_peak_end.h"
#include "dem/specimen/pressure_boundary.h"

#include <array>

#include "dem/laws/linear_law.h"
#include "dem/measure/measurement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace demfem::dem
{
  void LabTestParams::validate(const std::string &where, int dim,
                               const std::string &key_prefix) const
  {
    const double inf   = HUGE_VAL;
    const auto   check = [&](const char *key, double value, double lo, double hi,
                           bool lo_open = false, bool hi_open = false) {
      check_range(where, key_prefix + key, value, lo, hi, lo_open, hi_open);
    };
    check("brazilian diameter", brazilian_diameter, 0, inf);
    check("brazilian thickness", brazilian_thickness, 0, inf);
    check("brazilian flat angle", brazilian_flat_angle, 0, max_brazilian_flat_angle);
    if (brazilian_thickness > 0 && !(dim == 3 && brazilian_diameter > 0))
      throw InputError(where + ": " + key_prefix +
                       "brazilian thickness: only for a 3D Brazilian specimen of its "
                       "own (" +
                       key_prefix + "brazilian diameter > 0); allowed: 0");
    check("confining pressure", Pc, 0, inf);
    check("strain rate", strain_rate, 0, inf, true, false);
    check("load fraction", load_fraction, 0, 1, true, true);
    check("strain limit", strain_limit, 0, 1, true, false);
    check("step limit", double(step_limit), 1, inf);
    check("history interval", history_interval, 1, 1e9);
    check("seating ratio limit", ratio_limit, 0, 1, true, false);
    check("seating step limit", double(seat_step_limit), 0, inf);
    check("grip thickness", grip_thickness, 0, 0.5, true, true);
    check("platen friction", platen_friction, 0, inf);
    check("servo velocity limit", servo.v_limit, 0, inf);
    check("lateral wall segments", lateral_segments, 1, 1e6);
    if (dim == 3 && lateral_segments > 1)
      throw InputError(where + ": " + key_prefix +
                       "lateral wall segments = " + std::to_string(lateral_segments) +
                       ": flexible lateral walls are 2D only; allowed in 3D: 1");
    if (pressure_boundary && dim == 3)
      throw InputError(where + ": " + key_prefix +
                       "confining boundary = pressure: 2D only; allowed in 3D: walls");
    if (pressure_boundary && lateral_segments > 1)
      throw InputError(where + ": " + key_prefix +
                       "lateral wall segments = " + std::to_string(lateral_segments) +
                       ": the pressure boundary replaces the lateral walls; allowed "
                       "with confining boundary = pressure: 1");
    check("fit window low", fit_lo, 0, 1, false, true);
    check("fit window high", fit_hi, fit_lo, 1, true, false);
    check("fit window stress low", fit_stress_lo, 0, inf);
    if (fit_stress_hi > 0)
      check("fit window stress high", fit_stress_hi, fit_stress_lo, inf, true, false);
    check("crack initiation fraction", crack_initiation_fraction, 0, 1, true, false);
    check("crack volumetric strain fraction", crack_volumetric_fraction, 0, 1, true,
          true);
    check("brazilian split fraction", split_fraction, 0, 1, true, true);
    // 0 keeps the specimen's time step.
    check("time step safety", timestep_safety, 0, 1);
  }

  VesselParams brazilian_vessel(const VesselParams &v, const LabTestParams &p, int dim)
  {
    if (!own_brazilian_specimen(p))
      return v;
    VesselParams b = v;
    b.shape        = "box";
    b.W = b.H = p.brazilian_diameter;
    b.D       = dim == 3 ? (p.brazilian_thickness > 0 ? p.brazilian_thickness
                                                      : 0.5 * p.brazilian_diameter)
                         : v.D;
    return b;
  }

  const char *test_kind_name(TestKind k)
  {
    switch (k)
      {
      case TestKind::compression:
        return "compression";
      case TestKind::brazilian:
        return "brazilian";
      default:
        return "direct_tension";
      }
  }

  double ls_slope(const std::vector<double> &x, const std::vector<double> &y)
  {
    const std::size_t n = std::min(x.size(), y.size());
    if (n < 2)
      return std::numeric_limits<double>::quiet_NaN();
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < n; ++i)
      mx += x[i], my += y[i];
    mx /= n, my /= n;
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < n; ++i)
      sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
    return sxx > 0 ? sxy / sxx : std::numeric_limits<double>::quiet_NaN();
  }

  namespace
  {
    template <int dim>
    class Runner
    {
    public:
      static constexpr int ax = dim - 1; // axial direction (fistPkg Fig. 20)

      Runner(Specimen<dim> &s, const LabTestParams &p, const LabCallbacks<dim> &cb)
          : s_(s)
          , m_(s.model)
          , p_(p)
          , cb_(cb)
          , crack_base_(s.model.cracks.size())
      {
        r_.kind = p.kind;
        // Far enough that no grain reaches a removed wall during the test.
        far_ = 0;
        for (int a = 0; a < dim; ++a)
          far_ = std::max(far_, 2 * s.vessel.length(m_.walls, a));
      }

      LabTestResult run()
      {
        if (p_.kind == TestKind::compression)
          setup_compression();
        else if (p_.kind == TestKind::brazilian)
          setup_brazilian();
        else
          setup_tension();
        load();
        extract();
        if (cb_.snapshot)
          cb_.snapshot(s_, "end");
        return r_;
      }

    private:
      Specimen<dim>                        &s_;
      Model<dim>                           &m_;
      const LabTestParams                  &p_;
      const LabCallbacks<dim>              &cb_;
      LabTestResult                         r_;
      std::size_t                           crack_base_, counted_ = 0;
      std::size_t                           n_ten_ = 0, n_shear_ = 0;
      std::array<std::size_t, n_bond_types> n_type_{}; // by BondType
      double                                far_ = 0;
      // Confined compression: the servo of the seating keeps the lateral
      // walls at Pc through the loading phase.
      std::unique_ptr<Servo<dim>> servo_;
      // Or, 2D with LabTestParams::pressure_boundary, the pressure boundary
      // that replaces the lateral walls from the seating on (the servo then
      // drives the platens in the seating only).
      std::unique_ptr<PressureBoundary> pressure_boundary_;
      std::vector<std::uint32_t>        gauge_, grip_top_, grip_bottom_;
      double       L0_    = 0; // loading length (platen gap / grip distance)
      double       v_     = 0; // speed of each platen / grip
      std::int64_t step0_ = 0;
      double       time0_ = 0;
      /// The state of largest load over all loading steps (the strength).
      HistoryRow peak_state_ = [] {
        HistoryRow h;
        h.load = -HUGE_VAL;
        return h;
      }();

      void count_cracks()
      {
        for (; crack_base_ + counted_ < m_.cracks.size(); ++counted_)
          {
            const auto &c = m_.cracks[crack_base_ + counted_];
            (c.mode == 0 ? n_ten_ : n_shear_)++;
            if (c.type != BondType::none)
              ++n_type_[static_cast<int>(c.type)];
          }
      }

      void remove_walls(int a)
      {
        s_.vessel.translate_outward(m_.walls, a, far_);
        s_.vessel.set_velocity(m_.walls, a, 0);
      }

      // Ratio-average equilibrium (ft_eq), optionally with the servo on.
      void equilibrate(Servo<dim> *servo)
      {
        const std::int64_t start = m_.step_count();
        for (std::int64_t n = 0; n < p_.seat_step_limit; ++n)
          {
            if (servo)
              servo->update(m_);
            if (pressure_boundary_)
              apply_pressure_boundary();
            m_.step();
            if (n % 100 == 99)
              {
                const double ratio = m_.unbalanced_ratio();
                const bool   ok    = (!servo || servo->within_tolerance(m_)) &&
                                (!(ratio > p_.ratio_limit)); // NaN (no force) is at rest
                if (cb_.progress)
                  {
                    LabProgress g;
                    g.phase         = "seating";
                    g.step          = n + 1;
                    g.stress        = servo ? servo->pressure(m_, ax) : 0;
                    g.fraction_done = double(n) / p_.seat_step_limit;
                    cb_.progress(g);
                  }
                if (ok)
                  break;
              }
          }
        if (servo)
          servo->stop(m_);
        r_.seating_steps = m_.step_count() - start;
      }

      // The confining servo of the seating (loading = false) or of the
      // loading phase; docs/calibrate.md, "What the tests do".
      ServoParams servo_params(double H, bool loading) const
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

      void start_loading()
      {
        // Grain displacements and strains are reset after seating (§5.5).
        m_.particles.x0 = m_.particles.x;
        s_.vessel.reset_strain_reference(m_.walls);
        m_.reset_energy_baseline();
        step0_ = m_.step_count();
        time0_ = m_.time();
        for (int i = 0; i < 3; ++i)
          for (auto g : grains_in(m_, s_.vessel.regions[i]))
            gauge_.push_back(g);
        std::sort(gauge_.begin(), gauge_.end());
        gauge_.erase(std::unique(gauge_.begin(), gauge_.end()), gauge_.end());
        count_cracks();
        loading_crack0_     = crack_base_ + counted_;
        counted_base_ten_   = n_ten_;
        counted_base_type_  = n_type_;
        counted_base_shear_ = n_shear_;
      }
      std::size_t counted_base_ten_ = 0, counted_base_shear_ = 0;

      // Cracks counted since loading began, both modes.
      std::size_t loading_cracks() const
      {
        return n_ten_ - counted_base_ten_ + n_shear_ - counted_base_shear_;
      }
      std::size_t loading_crack0_ = 0; // index in m_.cracks of the first loading crack
      std::array<std::size_t, n_bond_types> counted_base_type_{};

      void setup_compression()
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
              if (a == ax ||
                  (p_.ctype != CompressionType::unconfined && !pressure_boundary_))
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
            r_.confining_boundary =
                s_.vessel.flexible(0) ? "flexible walls" : "rigid walls";
            const ServoParams sp        = servo_params(H, true);
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
      void make_lateral_walls_flexible(double H)
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

      bool servo_holds_confinement() const
      {
        return p_.kind == TestKind::compression &&
               p_.ctype == CompressionType::confined && servo_;
      }

      // The lateral pressures (compression positive) of the confining walls
      // or of the pressure boundary (its two sides' mean).
      std::array<double, dim> lateral_pressures() const
      {
        std::array<double, dim> P{};
        for (int a = 0; a < dim - 1; ++a)
          P[a] = pressure_boundary_ ? 0.5 * (pressure_boundary_->pressure(0) +
                                             pressure_boundary_->pressure(1))
                                    : servo_->pressure(m_, a);
        return P;
      }

      // P_c on the outermost grains between the platens (2D).
      void apply_pressure_boundary()
      {
        if constexpr (dim == 2)
          {
            const auto &W = m_.walls;
            pressure_boundary_->apply(m_.particles, W.vertex[s_.vessel.lo_vertex[ax]][ax],
                                      W.vertex[s_.vessel.hi_vertex[ax]][ax]);
          }
      }

      // The confining pressure as the specimen feels it (docs/calibrate.md,
      // "Confining servo"): the specimen cannot respond as a whole faster
      // than a compression wave crosses it, so each servo-controlled wall's
      // pressure is averaged over windows of that crossing time, W / c with
      // W the smallest lateral size and c = sqrt(E* / rho) (E* of the
      // contacts: an upper bound of the assembly's wave speed, so the
      // shortest window). Every step is sampled, so the deviation does not
      // depend on the history interval; the single-step spikes are kept
      // apart.
      struct ConfinementGauge
      {
        double                  Pc = 0, window = 0, elapsed = 0;
        int                     n_lateral = 0;
        std::array<double, dim> sum{};
        double                  averaged = 0, spike = 0; // largest deviations

        void add(const std::array<double, dim> &pressures, double dt)
        {
          elapsed += dt;
          for (int a = 0; a < n_lateral; ++a)
            {
              const double P = pressures[a];
              spike          = std::max(spike, std::abs(P - Pc) / Pc);
              sum[a] += P * dt;
            }
          if (elapsed < window)
            return;
          for (int a = 0; a < n_lateral; ++a)
            averaged = std::max(averaged, std::abs(sum[a] / elapsed - Pc) / Pc);
          sum.fill(0);
          elapsed = 0;
        }
      };

      // sqrt(E* / rho) with the contacts' E*: an upper bound of the
      // assembly's compression-wave speed (0 without a modulus).
      double wave_speed() const
      {
        const double E = std::max(s_.material.emod, s_.material.lnm_emod);
        return std::sqrt(E / s_.material.density);
      }

      ConfinementGauge confinement_gauge() const
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

      void setup_brazilian()
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
      void seat_brazilian()
      {
        const double Fseat = s_.material.Pm * M_PI * r_.R * r_.t;
        if (!(Fseat > 0))
          return;
        const auto  &W  = m_.walls;
        const double vs = 0.5 * p_.strain_rate * s_.vessel.length(W, ax);
        s_.vessel.set_velocity(m_.walls, ax, -vs);
        for (std::int64_t n = 0; n < p_.step_limit; ++n)
          {
            m_.step();
            const double F = -0.5 * (W.wall_force(s_.vessel.lo[ax])[ax] -
                                     W.wall_force(s_.vessel.hi[ax])[ax]);
            if (F >= Fseat)
              break;
          }
        s_.vessel.set_velocity(m_.walls, ax, 0);
      }

      // Grain-platen contacts: the grain-wall linear law with friction.
      void platen_friction()
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
        const double         krat = s_.material.lnm_krat > 0 ? s_.material.lnm_krat : 1.0;
        const double         friction      = p_.platen_friction;
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

      void setup_tension()
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

      void hold(std::uint32_t i, double v)
      {
        m_.particles.fixity[i] = fix_all;
        m_.particles.v[i].setZero();
        m_.particles.v[i][ax] = v;
        m_.particles.w[i].setZero();
      }

      Tensor<dim> region_average() const
      {
        Tensor<dim> s     = Tensor<dim>::Zero();
        double      V     = 0;
        const int   first = p_.kind == TestKind::brazilian ? 1 : 0;
        const int   last  = p_.kind == TestKind::brazilian ? 1 : 2;
        for (int i = first; i <= last; ++i)
          {
            const auto &reg = s_.vessel.regions[i];
            s += reg.volume() * region_stress(m_, reg);
            V += reg.volume();
          }
        return V > 0 ? Tensor<dim>(s / V) : s;
      }

      // The load, axial force, stress and strain of the current state (the
      // walls' or grips' forces: cheap enough for every step).
      HistoryRow load_state() const
      {
        HistoryRow h;
        h.time = m_.time() - time0_;
        if (p_.kind == TestKind::compression)
          {
            h.axial_strain = s_.vessel.wall_strain(m_.walls, ax);
            // Wall-based axial stress over the initial cross-section (fn. 39).
            const auto &W  = m_.walls;
            h.axial_force  = 0.5 * (W.wall_force(s_.vessel.lo[ax])[ax] -
                                   W.wall_force(s_.vessel.hi[ax])[ax]);
            h.axial_stress = h.axial_force / r_.area;
            double lateral = 0; // deviator = |sigma_a - sigma_r| (Table 10)
            if (pressure_boundary_)
              lateral = -lateral_pressures()[0];
            else if (p_.ctype != CompressionType::unconfined)
              {
                for (int a = 0; a < dim - 1; ++a)
                  lateral += s_.vessel.wall_stress(W, a);
                lateral /= dim - 1;
              }
            h.lateral_wall_stress = lateral;
            h.load                = lateral - h.axial_stress;
          }
        else if (p_.kind == TestKind::brazilian)
          {
            const auto  &W = m_.walls;
            const double g = s_.vessel.length(W, ax);
            h.axial_strain = (g - L0_) / L0_; // Eq. 23
            // Eq. 22: F_a = (F_bottom - F_top)/2 along y, tension positive.
            h.axial_force = 0.5 * (W.wall_force(s_.vessel.lo[ax])[ax] -
                                   W.wall_force(s_.vessel.hi[ax])[ax]);
            h.axial_stress =
                -brazilian_strength(-h.axial_force, r_.R, r_.t, p_.brazilian_flat_angle);
            h.load = -h.axial_force;
          }
        else
          {
            h.axial_strain = 2 * v_ * h.time / L0_;
            // Force the specimen exerts on the grips, both ends averaged.
            double Ftop = 0, Fbot = 0;
            for (auto i : grip_top_)
              Ftop += m_.particles.f[i][ax];
            for (auto i : grip_bottom_)
              Fbot += m_.particles.f[i][ax];
            h.axial_force  = 0.5 * (Fbot - Ftop);
            h.axial_stress = h.axial_force / r_.area;
            h.load         = h.axial_stress;
          }
        return h;
      }

      HistoryRow record()
      {
        count_cracks();
        HistoryRow h     = load_state();
        h.step           = m_.step_count() - step0_;
        h.cracks_tension = n_ten_ - counted_base_ten_;
        h.cracks_shear   = n_shear_ - counted_base_shear_;
        const Tensor<dim> eg =
            gauge_.size() > dim ? gauge_strain(m_, gauge_) : Tensor<dim>::Zero();
        h.gauge_axial_strain    = eg(ax, ax);
        h.lateral_strain        = (eg.trace() - eg(ax, ax)) / (dim - 1);
        h.volumetric_strain     = eg.trace();
        const Tensor<dim> sr    = region_average();
        h.region_axial_stress   = sr(ax, ax);
        h.region_lateral_stress = (sr.trace() - sr(ax, ax)) / (dim - 1);
        return h;
      }

      void load()
      {
        const std::int64_t nmax = p_.step_limit;
        r_.ended_by             = "step limit";
        double peak             = -HUGE_VAL;
        // A failure crosses the specimen: a splitting or shear crack breaks
        // about one contact per grain it passes, some N^(1/dim) of them. A
        // drop when the test has cracked fewer contacts in all than a
        // quarter of that is a local event (a grain crushed under a
        // Brazilian platen: measured, 2 cracks dropped a 1000-grain disk's
        // load by 10 % at a quarter of its strength, and the load would
        // have risen again).
        const std::size_t failure_cracks = std::max<std::size_t>(
            1, static_cast<std::size_t>(
                   0.25 * std::pow(double(m_.particles.size()), 1.0 / dim)));
        // The post-peak rule averages the load over the round trip of a
        // compression wave along the loaded length (post_peak_end.h).
        const double round_trip = wave_speed() > 0 ? 2 * L0_ / wave_speed() : 0;
        PostPeakEnd  post_peak(p_.load_fraction, failure_cracks, round_trip);
        const bool   track_pc =
            (servo_holds_confinement() || pressure_boundary_) && p_.Pc > 0;
        ConfinementGauge confinement;
        if (track_pc)
          confinement = confinement_gauge();
        // Automatic loading limit of the confining servo (servo_params):
        // besides P_c, a crack burst can unload the specimen locally by up
        // to the axial stress, which a surface then leaves at
        // 2 |sigma_a| / (rho c); the walls must be able to follow
        // (docs/calibrate.md, "Confining servo"). Updated every step from
        // the previous step's axial stress.
        const bool auto_limit =
            servo_holds_confinement() && !(p_.servo.v_limit > 0) && wave_speed() > 0;
        const double base_limit =
            servo_holds_confinement() ? servo_->velocity_limit() : 0;
        double axial_now = 0;
        for (std::int64_t n = 1; n <= nmax; ++n)
          {
            if (auto_limit)
              servo_->set_velocity_limit(
                  std::max(base_limit, 2 * std::abs(axial_now) /
                                           (s_.material.density * wave_speed())));
            if (servo_holds_confinement())
              servo_->update(m_);
            if (pressure_boundary_)
              apply_pressure_boundary();
            m_.step();
            if (track_pc)
              confinement.add(lateral_pressures(), m_.timestep());
            // The strength is the largest load of any step, not of the
            // history rows: it must not depend on Tests/history interval
            // (rows every 50 steps read a 2D UCS 0.08 % low, measured).
            const HistoryRow now = load_state();
            axial_now            = now.axial_stress;
            if (now.load > peak_state_.load)
              {
                peak_state_ = now;
                if (track_pc)
                  {
                    r_.confining_deviation_to_peak = confinement.averaged;
                    r_.confining_spike_to_peak     = confinement.spike;
                    if (servo_)
                      r_.confining_velocity_limit = servo_->velocity_limit();
                  }
              }
            // The post-peak end and the strain limit are judged every step
            // (the rule on its own time windows): where a test ends must not
            // depend on the history rows.
            bool failed = false;
            if (post_peak.add_step(m_.timestep(), now.load))
              {
                count_cracks();
                failed = post_peak.failed(loading_cracks());
              }
            const bool at_strain_limit = std::abs(now.axial_strain) >= p_.strain_limit;
            if (n % p_.history_interval != 0 && n != nmax && !at_strain_limit && !failed)
              continue;
            const HistoryRow h = record();
            r_.history.push_back(h);
            const std::size_t cracks = h.cracks_tension + h.cracks_shear;
            if (h.load > peak)
              {
                peak        = h.load;
                r_.peak_row = r_.history.size() - 1;
                if (cb_.snapshot)
                  cb_.snapshot(s_, "peak");
              }
            const double reference = post_peak.reference_peak();
            double       done      = std::abs(h.axial_strain) / p_.strain_limit;
            if (reference > 0 && h.load < reference)
              done = std::max(done, (reference - h.load) /
                                        (reference * (1 - p_.load_fraction)));
            if (cb_.progress)
              {
                LabProgress g;
                g.phase         = test_kind_name(p_.kind);
                g.step          = h.step;
                g.stress        = h.axial_stress;
                g.strain        = h.axial_strain;
                g.cracks        = cracks;
                g.fraction_done = std::min(1.0, done);
                cb_.progress(g);
              }
            if (failed)
              {
                r_.ended_by = "post-peak";
                break;
              }
            if (std::abs(h.axial_strain) >= p_.strain_limit)
              {
                r_.ended_by = "strain limit";
                break;
              }
          }
        if (track_pc)
          {
            r_.confining_deviation = confinement.averaged;
            r_.confining_window    = confinement.window;
          }
        if (servo_)
          servo_->stop(m_);
        if constexpr (dim == 2)
          if (pressure_boundary_)
            pressure_boundary_->remove(m_.particles);
        for (int a = 0; a < dim; ++a)
          s_.vessel.set_velocity(m_.walls, a, 0);
        for (auto i : grip_top_)
          m_.particles.v[i].setZero();
        for (auto i : grip_bottom_)
          m_.particles.v[i].setZero();
        r_.loading_steps = m_.step_count() - step0_;
      }

      // Crack-damage stress: axial stress at the most compacted state
      // (smallest gauge volumetric strain, tension positive) before the
      // peak; from there on dilatancy outruns the elastic compaction. NaN
      // when the volume is smallest at the peak row itself (no reversal).
      double volumetric_reversal_stress() const
      {
        const auto &H   = r_.history;
        std::size_t min = 0;
        for (std::size_t i = 1; i <= r_.peak_row; ++i)
          if (H[i].volumetric_strain < H[min].volumetric_strain)
            min = i;
        return min < r_.peak_row ? std::abs(H[min].axial_stress)
                                 : std::numeric_limits<double>::quiet_NaN();
      }

      /// The modulus fit window as fractions of this test's peak load:
      /// LabTestParams::fit_lo/hi, or its stress window if one is given.
      double fit_window_low() const
      {
        return p_.fit_stress_hi > 0 ? p_.fit_stress_lo / r_.peak_load : p_.fit_lo;
      }
      double fit_window_high() const
      {
        return p_.fit_stress_hi > 0 ? p_.fit_stress_hi / r_.peak_load : p_.fit_hi;
      }

      /// Crack initiation by the crack volumetric strain
      /// (dem/specimen/crack_initiation.h); H.size() if it does not apply.
      std::size_t volumetric_crack_initiation_row(double E, double nu) const
      {
        CompressionBranch b;
        for (const auto &h : r_.history)
          {
            b.volumetric_strain.push_back(h.volumetric_strain);
            b.axial_stress.push_back(h.axial_stress);
            b.load.push_back(h.load);
          }
        b.peak_row = r_.peak_row;
        return crack_volumetric_initiation_row(b, E, nu, dim - 1, fit_window_low(),
                                               fit_window_high(),
                                               p_.crack_volumetric_fraction);
      }

      // Brazilian failure mode from the loading phase's cracks (in order of
      // breakage; the first n_peak are those of the peak row): decided on
      // the failure's cracks (brazilian_failure_cracks), with the fractions
      // of all cracks at the peak and at the end reported beside it.
      void classify_failure(std::size_t n_peak)
      {
        std::vector<Vec<dim>> all;
        for (std::size_t k = loading_crack0_; k < m_.cracks.size(); ++k)
          all.push_back(m_.cracks[k].position);
        n_peak = std::min(n_peak, all.size());
        const std::size_t n_fail =
            brazilian_failure_cracks(n_peak, all.size(), m_.particles.size(), dim);
        const Vec<dim> &c        = s_.vessel.center; // the disk's (setup_brazilian)
        auto            classify = [&](std::size_t from, std::size_t to) {
          return classify_brazilian_failure(
                         std::vector<Vec<dim>>(all.begin() + from, all.begin() + to), c, r_.R,
                         p_.split_fraction);
        };
        const auto failure     = classify(all.size() - n_fail, all.size());
        r_.failure_mode        = failure.mode;
        r_.split_fraction      = failure.fraction;
        r_.failure_cracks      = n_fail;
        r_.split_fraction_peak = classify(0, n_peak).fraction;
        r_.split_fraction_end  = classify(0, all.size()).fraction;
      }

      void extract()
      {
        const auto &H = r_.history;
        if (H.empty())
          return;
        // Strength and strain at the peak from the step of largest load;
        // crack counts, region stress and the modulus fit from the history
        // rows up to the row of largest load (peak_row).
        const HistoryRow &pk = H[r_.peak_row];
        const HistoryRow &ps = peak_state_.load >= pk.load ? peak_state_ : pk;
        r_.peak_load         = ps.load;
        r_.peak_strain       = std::abs(ps.axial_strain);
        r_.peak              = std::abs(ps.axial_stress);
        if (p_.kind == TestKind::brazilian)
          {
            r_.peak_force = -ps.axial_force;
            r_.peak       = brazilian_strength(r_.peak_force, r_.R, r_.t,
                                               p_.brazilian_flat_angle); // Eq. 24
            classify_failure(pk.cracks_tension + pk.cracks_shear);
          }
        r_.cracks_tension_peak = pk.cracks_tension;
        r_.cracks_shear_peak   = pk.cracks_shear;
        r_.cracks_tension      = H.back().cracks_tension;
        r_.cracks_shear        = H.back().cracks_shear;
        // As counted by the last history row (record() counts the cracks).
        for (int t = 0; t < n_bond_types; ++t)
          r_.cracks_by_type[t] = n_type_[t] - counted_base_type_[t];
        const double n_peak    = double(pk.cracks_tension + pk.cracks_shear);
        const double threshold = std::max(1.0, p_.crack_initiation_fraction * n_peak);
        for (std::size_t i = 0; i <= r_.peak_row; ++i)
          if (H[i].cracks_tension + H[i].cracks_shear >= threshold)
            {
              r_.crack_initiation       = std::abs(H[i].axial_stress);
              r_.crack_initiation_count = r_.crack_initiation;
              r_.crack_initiation_load  = H[i].load;
              break;
            }
        if (p_.kind == TestKind::direct_tension)
          {
            r_.peak_region = -HUGE_VAL;
            for (const auto &h : H)
              r_.peak_region = std::max(r_.peak_region, h.region_axial_stress);
          }
        if (p_.kind != TestKind::compression)
          return;
        r_.peak_region  = std::abs(pk.region_axial_stress);
        r_.crack_damage = volumetric_reversal_stress();
        // Elastic constants from the loading branch between fit_lo and
        // fit_hi of the peak deviator (fistPkg §5.2), or in the given stress
        // window: strains gauge based (the specimen itself, free of the
        // grain-platen compliance), axial stress wall based.
        std::vector<double> ea, er, sa, ew;
        const double        lo = fit_window_low() * r_.peak_load;
        const double        hi = fit_window_high() * r_.peak_load;
        for (std::size_t i = 0; i <= r_.peak_row; ++i)
          if (H[i].load >= lo && H[i].load <= hi)
            {
              ea.push_back(H[i].gauge_axial_strain);
              er.push_back(H[i].lateral_strain);
              sa.push_back(H[i].axial_stress);
              ew.push_back(H[i].axial_strain);
            }
        const double E  = ls_slope(ea, sa);  // Eq. 18/19: d sigma_a / d eps_a
        const double nu = -ls_slope(ea, er); // -d eps_r / d eps_a
        r_.E_wall       = ls_slope(ew, sa);
        if (p_.ctype == CompressionType::uniaxial_strain)
          {
            r_.E = E; // constrained modulus
            return;
          }
        const std::size_t ci = volumetric_crack_initiation_row(E, nu);
        if (ci < H.size())
          {
            r_.crack_initiation_volumetric = std::abs(H[ci].axial_stress);
            if (p_.crack_initiation_method == CrackInitiationMethod::volumetric_strain)
              {
                r_.crack_initiation      = r_.crack_initiation_volumetric;
                r_.crack_initiation_load = H[ci].load;
              }
          }
        else if (p_.crack_initiation_method == CrackInitiationMethod::volumetric_strain)
          r_.crack_initiation = r_.crack_initiation_load =
              std::numeric_limits<double>::quiet_NaN();
        if (dim == 3)
          r_.E = E, r_.nu = nu;
        else
          {
            r_.E_ps = E, r_.nu_ps = nu;
            plane_stress_to_plane_strain(E, nu, r_.E, r_.nu);
          }
      }
    };
  } // namespace

  template <int dim>
  LabTestResult run_lab_test(Specimen<dim> &s, const LabTestParams &p,
                             const LabCallbacks<dim> &cb)
  {
    p.validate("lab test", dim);
    if (p.timestep_safety > 0)
      s.model.safety_factor = p.timestep_safety;
    Runner<dim> r(s, p, cb);
    return r.run();
  }

  template LabTestResult run_lab_test<2>(Specimen<2> &, const LabTestParams &,
                                         const LabCallbacks<2> &);
  template LabTestResult run_lab_test<3>(Specimen<3> &, const LabTestParams &,
                                         const LabCallbacks<3> &);
} // namespace demfem::dem
