#include "coupling/tunnel_result.h"

#include "dem/io/json_number.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace demfem::coupling
{
  namespace
  {
    const std::pair<RunStatus, const char *> status_names[] = {
        {RunStatus::ok, "ok"},
        {RunStatus::diverged, "diverged"},
        {RunStatus::time_not_advancing, "time_not_advancing"},
        {RunStatus::in_situ_not_reached, "in_situ_not_reached"},
        {RunStatus::not_equilibrated, "not_equilibrated"},
        {RunStatus::region_too_small, "region_too_small"}};

    std::string g(double x)
    {
      std::ostringstream s;
      s << std::setprecision(4) << x;
      return s.str();
    }

  } // namespace

  std::string status_name(RunStatus s)
  {
    for (const auto &[v, n] : status_names)
      if (v == s)
        return n;
    return "unknown";
  }

  RunStatus status_from_name(const std::string &name)
  {
    for (const auto &[v, n] : status_names)
      if (name == n)
        return v;
    throw std::invalid_argument(
        "unknown run status '" + name +
        "' (allowed: ok, diverged, time_not_advancing, "
        "in_situ_not_reached, not_equilibrated, region_too_small)");
  }

  int exit_code(RunStatus s)
  {
    // 1 is bad input or an error before the run; 130/143 a stop on request.
    switch (s)
      {
      case RunStatus::ok:
        return 0;
      case RunStatus::diverged:
        return 2;
      case RunStatus::not_equilibrated:
        return 3;
      case RunStatus::in_situ_not_reached:
        return 4;
      case RunStatus::region_too_small:
        return 5;
      case RunStatus::time_not_advancing:
        return 6;
      }
    return 1;
  }

  double in_situ_error(const Eigen::Matrix2d &stress, const Eigen::Matrix2d &sigma0)
  {
    const double scale =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(sigma0, Eigen::EigenvaluesOnly)
            .eigenvalues()
            .cwiseAbs()
            .maxCoeff();
    return scale > 0 ? (stress - sigma0).cwiseAbs().maxCoeff() / scale : 0.0;
  }

  void assess_outcome(TunnelResult &r)
  {
    r.problems.clear();
    auto fail = [&](RunStatus s, const std::string &what) {
      r.problems.push_back({s, what});
    };
    if (r.diverged)
      fail(RunStatus::diverged, r.diagnosis);
    else
      {
        // Time advancing: a step of dt must add dt to t. A time step lost in
        // the round-off of t (absurd stiffness: dt ~ 1e-150 s) runs steps in
        // which nothing physical happens; half the expected advance is far
        // from both that and from a step that varies within a phase.
        for (const auto &ph : r.phases)
          if (ph.steps > 0 &&
              !(ph.time_end - ph.time_start >= 0.5 * ph.steps * ph.timestep))
            fail(RunStatus::time_not_advancing,
                 "phase '" + ph.name + "': model time advanced by " +
                     g(ph.time_end - ph.time_start) + " s in " +
                     std::to_string(ph.steps) + " steps of " + g(ph.timestep) +
                     " s: the time step is lost in round-off (check the stiffnesses and "
                     "densities)");
        // In-situ state: the centre disk carries sigma0 before excavation.
        r.in_situ_error = in_situ_error(r.region_stress_before, r.sigma0);
        if (!r.phases.empty() && !(r.in_situ_error <= r.in_situ_tolerance))
          fail(RunStatus::in_situ_not_reached,
               "region stress before excavation [" + g(r.region_stress_before(0, 0)) +
                   ", " + g(r.region_stress_before(1, 1)) + ", " +
                   g(r.region_stress_before(0, 1)) + "] Pa against sigma0 [" +
                   g(r.sigma0(0, 0)) + ", " + g(r.sigma0(1, 1)) + ", " +
                   g(r.sigma0(0, 1)) + "] Pa: error " + g(100 * r.in_situ_error) +
                   " % of |sigma0| > " + g(100 * r.in_situ_tolerance) +
                   " % (Tunnel/in situ tolerance)");
        // sigma0 reached by the servo, but only with an interface strain
        // that makes the region another material than the continuum
        // (coupling/in_situ_servo.h, contrast_limit).
        if (!r.phases.empty() && r.servo.relative_strain > servo_contrast_limit)
          fail(RunStatus::in_situ_not_reached,
               "the in-situ servo needed an interface strain of " +
                   g(100 * r.servo.relative_strain) + " % of the in-situ strain (limit " +
                   g(100 * servo_contrast_limit) +
                   " %) to bring the region to sigma0: the region's stiffness is not the "
                   "continuum's (fitted region / "
                   "continuum: lambda + mu " +
                   g(r.servo.stiffness_ratios[0]) + ", mu " +
                   g(r.servo.stiffness_ratios[1]) +
                   "); give the continuum the region's E and nu (Continuum/young "
                   "modulus, Continuum/poisson ratio, or the material file). Tunnel/in "
                   "situ tolerance judges the stress itself");
        for (const auto &ph : r.phases)
          if (!ph.equilibrated)
            fail(RunStatus::not_equilibrated,
                 "phase '" + ph.name + "' ended at its " +
                     (ended_at_time_limit(ph, r.phase_time_limit)
                          ? "time limit (" + g(ph.time_end - ph.time_start) +
                                " s, Coupling/phase time limit)"
                          : "step limit (" + std::to_string(ph.steps) +
                                " steps, Coupling/step limit)") +
                     ": unbalanced "
                     "ratio " +
                     g(ph.unbalanced_ratio) + ", continuum kinetic energy " +
                     g(ph.kinetic_energy_ratio) + " of its peak, interface residual " +
                     g(ph.interface_residual) + " (targets " + g(r.ratio_tolerance) +
                     ", " + g(kinetic_energy_target) + ", " + g(r.ratio_tolerance) + ")");
        if (r.region_too_small)
          fail(RunStatus::region_too_small,
               std::to_string(r.zone_cracks_near_interface) +
                   " cracks of the damage zone (connected to the wall) within two "
                   "grain diameters of the coupling boundary: the DEM region (radius " +
                   g(r.dem_region_radius) +
                   " m) is too small for this damage; enlarge DEM region/radius or use "
                   "'auto'");
      }
    std::stable_sort(r.problems.begin(), r.problems.end(),
                     [](const auto &a, const auto &b) { return a.first < b.first; });
    r.status = r.problems.empty() ? RunStatus::ok : r.problems.front().first;
  }

  nlohmann::ordered_json summary_json(const TunnelResult &r)
  {
    using dem::json_number;
    using J     = nlohmann::ordered_json;
    auto tensor = [](const Eigen::Matrix2d &t) {
      return J::array({json_number(t(0, 0)), json_number(t(1, 1)), json_number(t(0, 1))});
    };
    J j;
    j["status"] = status_name(r.status);
    J problems  = J::array();
    for (const auto &[s, what] : r.problems)
      problems.push_back({{"status", status_name(s)}, {"message", what}});
    j["problems"] = problems;
    if (r.diverged)
      j["diagnosis"] = r.diagnosis;
    j["dimension"] = r.dimension;
    if (r.dimension == 3)
      {
        j["slab_thickness"]  = json_number(r.slab_thickness);
        j["embedding"]       = r.embedding;
        j["axial_extension"] = json_number(r.axial_extension);
      }
    j["variant"]                         = r.variant;
    j["scheme"]                          = r.scheme;
    j["n_particles"]                     = r.n_particles;
    j["n_contacts"]                      = r.n_contacts;
    j["n_fem_dofs"]                      = r.n_fem_dofs;
    j["steps"]                           = r.steps - r.packing_steps;
    j["packing_steps"]                   = r.packing_steps;
    j["genesis_steps"]                   = r.genesis_steps;
    j["genesis_reused"]                  = r.genesis_reused;
    j["genesis_wall_time_s"]             = json_number(r.genesis_wall_time_s);
    j["grain_resolution_a_over_d"]       = json_number(r.grain_resolution_a_over_d);
    j["timestep_s"]                      = json_number(r.timestep);
    j["dem_critical_timestep_s"]         = json_number(r.critical_timestep);
    j["in_situ_ramp"]                    = {{"duration_s", json_number(r.ramp_duration)},
                                            {"crossing_time_s", json_number(r.ramp_crossing_time)},
                                            {"steps", r.ramp_steps}};
    j["wall_time_s"]                     = json_number(r.wall_time_s);
    j["cracks_total"]                    = r.cracks_total;
    j["cracks_tensile"]                  = r.cracks_tensile;
    j["cracks_shear"]                    = r.cracks_shear;
    j["cracks_by_type"]                  = r.cracks_by_type;
    j["damage_zone_depth"]               = json_number(r.damage_zone_depth);
    j["damage_zone_depth_max"]           = json_number(r.damage_zone_depth_max);
    j["damage"]                          = r.damage.to_json();
    j["elastic_initiation_zones"]        = to_json(r.initiation_zones);
    j["cracks_before_excavation"]        = r.cracks_before_excavation;
    j["cracks_near_interface"]           = r.cracks_near_interface;
    j["zone_cracks_near_interface"]      = r.zone_cracks_near_interface;
    j["region_too_small"]                = r.region_too_small;
    j["dem_region_radius"]               = json_number(r.dem_region_radius);
    j["wall_convergence_mean"]           = json_number(r.wall_convergence_mean);
    j["wall_particles"]                  = r.n_wall_particles;
    j["interface_force_imbalance_max"]   = json_number(r.interface_force_imbalance_max);
    j["in_situ_stress"]                  = tensor(r.sigma0);
    j["region_stress_before_excavation"] = tensor(r.region_stress_before);
    if (r.dimension == 3)
      j["region_stress_zz_before_excavation"] = json_number(r.region_stress_before_zz);
    j["in_situ_error"]     = json_number(r.in_situ_error);
    j["in_situ_tolerance"] = json_number(r.in_situ_tolerance);
    {
      J errors = J::array();
      for (double e : r.servo.errors)
        errors.push_back(json_number(e));
      j["in_situ_servo"] = {
          {"tolerance", json_number(r.servo.tolerance)},
          {"errors", errors},
          {"converged", r.servo.converged},
          {"interface_strain", tensor(r.servo.interface_strain)},
          {"interface_strain_over_in_situ_strain", json_number(r.servo.relative_strain)},
          {"region_over_continuum_stiffness",
           {{"lambda_plus_mu", json_number(r.servo.stiffness_ratios[0])},
            {"mu", json_number(r.servo.stiffness_ratios[1])}}}};
    }
    j["equilibrium_ratio"] = json_number(r.ratio_tolerance);
    J phases               = J::array();
    for (const auto &ph : r.phases)
      phases.push_back({{"name", ph.name},
                        {"steps", ph.steps},
                        {"equilibrated", ph.equilibrated},
                        {"time_start_s", json_number(ph.time_start)},
                        {"time_end_s", json_number(ph.time_end)},
                        {"unbalanced_ratio", json_number(ph.unbalanced_ratio)},
                        {"kinetic_energy_ratio", json_number(ph.kinetic_energy_ratio)},
                        {"interface_residual", json_number(ph.interface_residual)}});
    j["phases"] = phases;
    J costs     = J::array();
    for (const auto &ph : r.phases)
      costs.push_back({{"name", ph.name},
                       {"steps", ph.steps},
                       {"wall_time_s", json_number(ph.wall_time_s)},
                       {"continuum_s", json_number(ph.continuum_s)},
                       {"dem_s", json_number(ph.dem_s)},
                       {"interface_s", json_number(ph.interface_s)},
                       {"criterion_s", json_number(ph.criterion_s)},
                       {"output_s", json_number(ph.output_s)}});
    j["phase_costs"] = costs;
    return j;
  }

  std::string phases_to_text(const std::vector<PhaseRecord> &phases)
  {
    // One line per phase; the name last (it has blanks). Round-trip precision
    // so that a restarted run writes the same summary.
    std::ostringstream s;
    s << std::setprecision(17);
    for (const auto &ph : phases)
      s << ph.steps << " " << ph.time_start << " " << ph.time_end << " " << ph.timestep
        << " " << ph.unbalanced_ratio << " " << ph.kinetic_energy_ratio << " "
        << ph.interface_residual << " " << ph.equilibrated << " " << ph.wall_time_s << " "
        << ph.continuum_s << " " << ph.dem_s << " " << ph.interface_s << " "
        << ph.criterion_s << " " << ph.output_s << " " << ph.kinetic_energy_peak << " "
        << ph.name << "\n";
    return s.str();
  }

  std::vector<PhaseRecord> phases_from_text(const std::string &text)
  {
    std::vector<PhaseRecord> r;
    std::istringstream       in(text);
    for (std::string line; std::getline(in, line);)
      {
        std::istringstream l(line);
        PhaseRecord        ph;
        if (!(l >> ph.steps >> ph.time_start >> ph.time_end >> ph.timestep >>
              ph.unbalanced_ratio >> ph.kinetic_energy_ratio >> ph.interface_residual >>
              ph.equilibrated >> ph.wall_time_s >> ph.continuum_s >> ph.dem_s >>
              ph.interface_s >> ph.criterion_s >> ph.output_s))
          throw std::invalid_argument("damaged phase record '" + line + "'");
        l >> std::ws;
        // The peak is optional (records written before it was stored): the
        // phase names do not start with a number.
        if (std::isdigit(l.peek()) && !(l >> ph.kinetic_energy_peak >> std::ws))
          throw std::invalid_argument("damaged phase record '" + line + "'");
        std::getline(l, ph.name);
        r.push_back(ph);
      }
    return r;
  }
} // namespace demfem::coupling
