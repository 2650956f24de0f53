// Laboratory tests: input checks, the loading phase and property
// extraction (see lab_tests.h; fistPkg §5.2, §5.4-5.7); each test's setup is
// in lab_test_setup.cc.
#include "dem/specimen/lab_tests.h"

#include "dem/measure/measurement.h"
#include "dem/specimen/brazilian_failure.h"
#include "dem/specimen/crack_initiation.h"
#include "dem/specimen/lab_test_runner.h"
#include "dem/specimen/post_peak_end.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

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
    check("confining tolerance", confining_tolerance, 0, 1, true, false);
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

  const char *crack_initiation_method_name(CrackInitiationMethod m)
  {
    switch (m)
      {
      case CrackInitiationMethod::crack_count:
        return "crack count";
      case CrackInitiationMethod::lateral_strain:
        return "lateral strain";
      default:
        return "volumetric strain";
      }
  }

  CrackInitiationMethod parse_crack_initiation_method(const std::string &name)
  {
    for (auto m :
         {CrackInitiationMethod::volumetric_strain, CrackInitiationMethod::crack_count,
          CrackInitiationMethod::lateral_strain})
      if (name == crack_initiation_method_name(m))
        return m;
    throw std::invalid_argument("crack initiation method '" + name +
                                "': must be one of " + crack_initiation_method_names);
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

} // namespace demfem::dem

namespace demfem::dem::lab_detail
{
  template <int dim>
  void Runner<dim>::count_cracks()
  {
    for (; crack_base_ + counted_ < m_.cracks.size(); ++counted_)
      {
        const auto &c = m_.cracks[crack_base_ + counted_];
        (c.mode == 0 ? n_ten_ : n_shear_)++;
        if (c.type != BondType::none)
          ++n_type_[static_cast<int>(c.type)];
      }
  }

  // Ratio-average equilibrium (ft_eq), optionally with the servo on.
  template <int dim>
  void Runner<dim>::equilibrate(Servo<dim> *servo)
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

  template <int dim>
  void Runner<dim>::start_loading()
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

  template <int dim>
  Tensor<dim> Runner<dim>::region_average() const
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
  template <int dim>
  HistoryRow Runner<dim>::load_state() const
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

  template <int dim>
  HistoryRow Runner<dim>::record()
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

  template <int dim>
  void Runner<dim>::load()
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
        1, static_cast<std::size_t>(0.25 *
                                    std::pow(double(m_.particles.size()), 1.0 / dim)));
    // The post-peak rule averages the load over the round trip of a
    // compression wave along the loaded length (post_peak_end.h).
    const double round_trip = wave_speed() > 0 ? 2 * L0_ / wave_speed() : 0;
    PostPeakEnd  post_peak(p_.load_fraction, failure_cracks, round_trip);
    const bool track_pc = (servo_holds_confinement() || pressure_boundary_) && p_.Pc > 0;
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
    const double base_limit = servo_holds_confinement() ? servo_->velocity_limit() : 0;
    double       axial_now  = 0;
    for (std::int64_t n = 1; n <= nmax; ++n)
      {
        if (auto_limit)
          servo_->set_velocity_limit(
              std::max(base_limit,
                       2 * std::abs(axial_now) / (s_.material.density * wave_speed())));
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
          done =
              std::max(done, (reference - h.load) / (reference * (1 - p_.load_fraction)));
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

  /// The history as a compression branch (dem/specimen/crack_initiation.h).
  template <int dim>
  CompressionBranch Runner<dim>::compression_branch() const
  {
    CompressionBranch b;
    for (const auto &h : r_.history)
      {
        b.volumetric_strain.push_back(h.volumetric_strain);
        b.lateral_strain.push_back(h.lateral_strain);
        b.axial_stress.push_back(h.axial_stress);
        b.load.push_back(h.load);
      }
    b.peak_row = r_.peak_row;
    return b;
  }

  /// Crack initiation by the crack volumetric strain (with the loading
  /// branch's E, nu) and by the lateral strain response
  /// (dem/specimen/crack_initiation.h); the chosen method's is
  /// crack_initiation (NaN where it does not apply).
  template <int dim>
  void Runner<dim>::read_crack_initiation(const CompressionBranch &b,
                                          const std::size_t damage, double E, double nu)
  {
    const auto  &H      = r_.history;
    const double nan    = std::numeric_limits<double>::quiet_NaN();
    auto         at_row = [&](std::size_t row) {
      return row < H.size() ? std::abs(H[row].axial_stress) : nan;
    };
    const std::size_t by_volume =
        crack_volumetric_initiation_row(b, E, nu, dim - 1, fit_window_low(),
                                        fit_window_high(), p_.crack_volumetric_fraction);
    const std::size_t by_lateral   = lateral_strain_initiation_row(b, damage);
    r_.crack_initiation_volumetric = at_row(by_volume);
    r_.crack_initiation_lateral    = at_row(by_lateral);
    if (p_.crack_initiation_method == CrackInitiationMethod::crack_count)
      return;
    const std::size_t row =
        p_.crack_initiation_method == CrackInitiationMethod::volumetric_strain
            ? by_volume
            : by_lateral;
    r_.crack_initiation      = at_row(row);
    r_.crack_initiation_load = row < H.size() ? H[row].load : nan;
  }

  // Brazilian failure mode from the loading phase's cracks (in order of
  // breakage; the first n_peak are those of the peak row): decided on
  // the failure's cracks (brazilian_failure_cracks), with the fractions
  // of all cracks at the peak and at the end reported beside it.
  template <int dim>
  void Runner<dim>::classify_failure(std::size_t n_peak)
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

  template <int dim>
  void Runner<dim>::extract()
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
    r_.peak_region                 = std::abs(pk.region_axial_stress);
    const CompressionBranch branch = compression_branch();
    const std::size_t       damage = volumetric_reversal_row(branch);
    r_.crack_damage                = damage < H.size() ? std::abs(H[damage].axial_stress)
                                                       : std::numeric_limits<double>::quiet_NaN();
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
    read_crack_initiation(branch, damage, E, nu);
    if (dim == 3)
      r_.E = E, r_.nu = nu;
    else
      {
        r_.E_ps = E, r_.nu_ps = nu;
        plane_stress_to_plane_strain(E, nu, r_.E, r_.nu);
      }
  }

  template class Runner<2>;
  template class Runner<3>;
} // namespace demfem::dem::lab_detail

namespace demfem::dem
{

  template <int dim>
  LabTestResult run_lab_test(Specimen<dim> &s, const LabTestParams &p,
                             const LabCallbacks<dim> &cb)
  {
    p.validate("lab test", dim);
    if (p.timestep_safety > 0)
      s.model.safety_factor = p.timestep_safety;
    lab_detail::Runner<dim> r(s, p, cb);
    return r.run();
  }

  template LabTestResult run_lab_test<2>(Specimen<2> &, const LabTestParams &,
                                         const LabCallbacks<2> &);
  template LabTestResult run_lab_test<3>(Specimen<3> &, const LabTestParams &,
                                         const LabCallbacks<3> &);
} // namespace demfem::dem
