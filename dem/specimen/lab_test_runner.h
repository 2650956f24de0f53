#pragma once
// The runner of one laboratory test (dem/specimen/lab_tests.h): set up the
// specimen for the test (compression with its confining boundary, the
// Brazilian disk, the direct-tension grips; lab_test_setup.cc), seat it,
// load it to failure and extract the properties (lab_tests.cc). Internal to
// the lab tests; run_lab_test() is the interface.
#include "dem/specimen/crack_initiation.h"
#include "dem/specimen/lab_tests.h"
#include "dem/specimen/pressure_boundary.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace demfem::dem::lab_detail
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

    // Setting up and seating each test (lab_test_setup.cc).
    void                    setup_compression();
    ServoParams             servo_params(double H, bool loading) const;
    void                    make_lateral_walls_flexible(double H);
    std::array<double, dim> lateral_pressures() const;
    void                    apply_pressure_boundary();
    ConfinementGauge        confinement_gauge() const;
    void                    setup_brazilian();
    void                    seat_brazilian();
    void                    platen_friction();
    void                    setup_tension();

    // Seating, loading and extraction (lab_tests.cc).
    void              equilibrate(Servo<dim> *servo);
    void              start_loading();
    void              load();
    HistoryRow        load_state() const;
    HistoryRow        record();
    Tensor<dim>       region_average() const;
    void              count_cracks();
    void              extract();
    CompressionBranch compression_branch() const;
    void read_crack_initiation(const CompressionBranch &branch, std::size_t damage_row,
                               double E, double nu);
    void classify_failure(std::size_t n_peak);

    void remove_walls(int a)
    {
      s_.vessel.translate_outward(m_.walls, a, far_);
      s_.vessel.set_velocity(m_.walls, a, 0);
    }

    // Grip grains neither translate nor spin except the axial pull.
    void hold(std::uint32_t i, double v)
    {
      m_.particles.fixity[i] = fix_all;
      m_.particles.v[i].setZero();
      m_.particles.v[i][ax] = v;
      m_.particles.w[i].setZero();
    }

    bool servo_holds_confinement() const
    {
      return p_.kind == TestKind::compression && p_.ctype == CompressionType::confined &&
             servo_;
    }

    // sqrt(E* / rho) with the contacts' E*: an upper bound of the
    // assembly's compression-wave speed (0 without a modulus).
    double wave_speed() const
    {
      const double E = std::max(s_.material.emod, s_.material.lnm_emod);
      return std::sqrt(E / s_.material.density);
    }

    // Cracks counted since loading began, both modes.
    std::size_t loading_cracks() const
    {
      return n_ten_ - counted_base_ten_ + n_shear_ - counted_base_shear_;
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

    Specimen<dim>                        &s_;
    Model<dim>                           &m_;
    const LabTestParams                  &p_;
    const LabCallbacks<dim>              &cb_;
    LabTestResult                         r_;
    std::size_t                           crack_base_, counted_ = 0;
    std::size_t                           n_ten_ = 0, n_shear_ = 0;
    std::array<std::size_t, n_bond_types> n_type_{}; // by BondType
    // The counts when loading began, and the index in m_.cracks of the
    // first loading crack.
    std::size_t                           counted_base_ten_ = 0, counted_base_shear_ = 0;
    std::array<std::size_t, n_bond_types> counted_base_type_{};
    std::size_t                           loading_crack0_ = 0;
    double                                far_            = 0;
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
  };
} // namespace demfem::dem::lab_detail
