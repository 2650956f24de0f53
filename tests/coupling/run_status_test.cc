// The outcome checks of a tunnel run (coupling/tunnel_result.h; docs/tunnel.md,
// "Run status and exit codes"): each check on a result built by hand, the
// order of severity, the summary fields and the phase records' round trip
// through a checkpoint's text.
#include "coupling/tunnel_result.h"

#include <catch2/catch.hpp>

#include <set>

using namespace demfem::coupling;

namespace
{
  // A result that passes every check: sigma0 = (-30, -60, 0) MPa reached to
  // 2 %, two phases equilibrated, time advanced by steps x dt.
  TunnelResult passing()
  {
    TunnelResult r;
    r.sigma0 << -30e6, 0, 0, -60e6;
    r.region_stress_before << -29.4e6, 0.3e6, 0.3e6, -59.0e6;
    r.in_situ_tolerance = 0.1;
    r.ratio_tolerance   = 1e-3;
    r.dem_region_radius = 3.5;
    for (const char *name : {"in-situ", "equilibrium"})
      {
        PhaseRecord ph;
        ph.name             = name;
        ph.steps            = 1000;
        ph.timestep         = 1e-5;
        ph.time_start       = 0.25;
        ph.time_end         = 0.26;
        ph.unbalanced_ratio = 4e-4;
        ph.equilibrated     = true;
        r.phases.push_back(ph);
      }
    return r;
  }
} // namespace

TEST_CASE("run status: a run that reached everything is ok", "[coupling][status]")
{
  TunnelResult r = passing();
  assess_outcome(r);
  CHECK(r.status == RunStatus::ok);
  CHECK(r.problems.empty());
  // max |difference| = 1.0 MPa over the largest |principal| 60 MPa.
  CHECK(r.in_situ_error == Approx(1.0 / 60).epsilon(1e-12));
}

TEST_CASE("run status: each failed check has its status and numbers",
          "[coupling][status]")
{
  SECTION("a phase ended at its step limit")
  {
    TunnelResult r               = passing();
    r.phases[1].equilibrated     = false;
    r.phases[1].unbalanced_ratio = 0.034;
    assess_outcome(r);
    CHECK(r.status == RunStatus::not_equilibrated);
    REQUIRE(r.problems.size() == 1);
    CHECK_THAT(r.problems[0].second, Catch::Contains("'equilibrium'") &&
                                         Catch::Contains("0.034") &&
                                         Catch::Contains("Coupling/step limit"));
  }
  SECTION("the in-situ stress is far from sigma0 (the stiffness-contrast probe)")
  {
    TunnelResult r = passing();
    r.region_stress_before << -4.9e3, 0, 0, -4.9e3; // measured: -4.9 kPa for -30 MPa
    assess_outcome(r);
    CHECK(r.status == RunStatus::in_situ_not_reached);
    CHECK(r.in_situ_error == Approx((60e6 - 4.9e3) / 60e6).epsilon(1e-12));
    CHECK_THAT(r.problems[0].second, Catch::Contains("Tunnel/in situ tolerance"));
  }
  SECTION("sigma0 reached by the in-situ servo, but only as another material")
  {
    TunnelResult r           = passing();
    r.region_stress_before   = r.sigma0; // the servo reached it
    r.servo.relative_strain  = 0.9999;   // a region 10^4 times stiffer
    r.servo.stiffness_ratios = {{1e4, 1e4}};
    assess_outcome(r);
    CHECK(r.status == RunStatus::in_situ_not_reached);
    REQUIRE(r.problems.size() == 1);
    CHECK_THAT(r.problems[0].second,
               Catch::Contains("99.99 % of the in-situ strain") &&
                   Catch::Contains("limit 50 %) to bring the region to sigma0") &&
                   Catch::Contains("Continuum/young modulus"));
    r.servo.relative_strain = 0.5; // the limit itself: reached
    assess_outcome(r);
    CHECK(r.status == RunStatus::ok);
  }
  SECTION("the tolerance is inclusive and relative to the largest principal")
  {
    TunnelResult r = passing();
    r.region_stress_before << -30e6, 0, 0, -54e6; // exactly 10 % of 60 MPa off
    assess_outcome(r);
    CHECK(r.status == RunStatus::ok);
    r.region_stress_before(1, 1) = -53.9e6; // just beyond
    assess_outcome(r);
    CHECK(r.status == RunStatus::in_situ_not_reached);
  }
  SECTION("a time step lost in the round-off of t")
  {
    TunnelResult r       = passing();
    r.phases[0].timestep = 1e-150; // emod = 1e300
    r.phases[0].time_end = r.phases[0].time_start;
    assess_outcome(r);
    CHECK(r.status == RunStatus::time_not_advancing);
  }
  SECTION("the damage zone at the coupling boundary")
  {
    TunnelResult r               = passing();
    r.region_too_small           = true;
    r.cracks_near_interface      = 9;
    r.zone_cracks_near_interface = 7;
    assess_outcome(r);
    CHECK(r.status == RunStatus::region_too_small);
    CHECK_THAT(r.problems[0].second, Catch::Contains("7 cracks of the damage zone"));
  }
  SECTION("a diverged run is not checked further")
  {
    TunnelResult r           = passing();
    r.diverged               = true;
    r.diagnosis              = "energy balance violated";
    r.phases[0].equilibrated = false;
    assess_outcome(r);
    CHECK(r.status == RunStatus::diverged);
    CHECK(r.problems.size() == 1);
  }
}

TEST_CASE("run status: several failures, the most severe first", "[coupling][status]")
{
  TunnelResult r               = passing();
  r.region_too_small           = true;
  r.phases[0].equilibrated     = false;
  r.region_stress_before(0, 0) = 0;
  assess_outcome(r);
  REQUIRE(r.problems.size() == 3);
  CHECK(r.status == RunStatus::in_situ_not_reached);
  CHECK(r.problems[1].first == RunStatus::not_equilibrated);
  CHECK(r.problems[2].first == RunStatus::region_too_small);
  const auto j = summary_json(r);
  CHECK(j["status"] == "in_situ_not_reached");
  CHECK(j["problems"].size() == 3);
  CHECK(j["phases"][0]["equilibrated"] == false);
  CHECK(j["in_situ_tolerance"] == Approx(0.1));
}

TEST_CASE("run status: names and exit codes are distinct and round-trip",
          "[coupling][status]")
{
  std::set<int>         codes;
  std::set<std::string> names;
  for (auto s : {RunStatus::ok, RunStatus::diverged, RunStatus::time_not_advancing,
                 RunStatus::in_situ_not_reached, RunStatus::not_equilibrated,
                 RunStatus::region_too_small})
    {
      CHECK(status_from_name(status_name(s)) == s);
      codes.insert(exit_code(s));
      names.insert(status_name(s));
      CHECK((exit_code(s) == 0) == (s == RunStatus::ok));
      CHECK(exit_code(s) != 1); // 1 is bad input
    }
  CHECK(codes.size() == 6);
  CHECK(names.size() == 6);
  CHECK_THROWS_AS(status_from_name("fine"), std::invalid_argument);
}

TEST_CASE("run status: phase records survive a checkpoint bit for bit",
          "[coupling][status]")
{
  TunnelResult r                   = passing();
  r.phases[0].name                 = "excavation 1/2";
  r.phases[0].unbalanced_ratio     = 1.0 / 3.0;
  r.phases[1].kinetic_energy_ratio = 9.449943734351944e-05;
  r.phases[1].equilibrated         = false;
  r.phases[1].wall_time_s          = 12.25;
  r.phases[1].dem_s                = 1.0 / 3.0;
  r.phases[1].kinetic_energy_peak  = 2.0 / 3.0e-7;
  const auto back                  = phases_from_text(phases_to_text(r.phases));
  REQUIRE(back.size() == 2);
  for (std::size_t k = 0; k < 2; ++k)
    {
      CHECK(back[k].name == r.phases[k].name);
      CHECK(back[k].steps == r.phases[k].steps);
      CHECK(back[k].time_end == r.phases[k].time_end); // exact: 17 digits
      CHECK(back[k].unbalanced_ratio == r.phases[k].unbalanced_ratio);
      CHECK(back[k].kinetic_energy_ratio == r.phases[k].kinetic_energy_ratio);
      CHECK(back[k].equilibrated == r.phases[k].equilibrated);
      CHECK(back[k].wall_time_s == r.phases[k].wall_time_s);
      CHECK(back[k].dem_s == r.phases[k].dem_s);
      CHECK(back[k].kinetic_energy_peak == r.phases[k].kinetic_energy_peak);
    }
  // A record written before the peak was stored still reads (peak 0).
  const auto old =
      phases_from_text("5900 0.2 0.3 1e-05 2e-05 9e-05 0 1 1 1 1 0 0 0 in-situ\n");
  REQUIRE(old.size() == 1);
  CHECK(old[0].name == "in-situ");
  CHECK(old[0].kinetic_energy_peak == 0);
  CHECK_THROWS_AS(phases_from_text("12 x\n"), std::invalid_argument);
}
