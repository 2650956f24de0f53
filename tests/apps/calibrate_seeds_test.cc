// `demfem calibrate` with Problem/seeds > 1 (apps/calibrate_seeds.cc): the
// material file holds the seed means, their scatter and the single values.
#include <catch2/catch.hpp>

#include "run_command.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

using demfem::testing::run_demfem;
using demfem::testing::run_with_threads;
using json = nlohmann::json;

namespace
{
  json read_json(const std::string &f)
  {
    std::ifstream in(f);
    return json::parse(in);
  }

  // The Lac du Bonnet example in a 12.5 x 25 mm vessel (about 250 grains),
  // UCS only, at 0.25 /s (twice the example's rate: the test is about the
  // seed statistics, not the rate): about 10 s per packing.
  std::string small(const std::string &dir)
  {
    return "calibrate " + std::string(DEMFEM_SOURCE_DIR) +
           "/apps/examples/lac_du_bonnet_2d.prm --set Tests/tests=ucs --set "
           "\"Tests/strain rate=0.25\" --set "
           "\"Tests/loading "
           "rate check=false\" --set Problem/vtk=false --set \"Material/number of "
           "grains=250\" --set Vessel/height=0.025 --set Vessel/width=0.0125 --set "
           "\"Problem/output directory=" +
           dir + "\"";
  }
} // namespace

TEST_CASE("calibrate: Problem/seeds = 2 writes the seed means, their scatter and values",
          "[calibrate][seeds][app]")
{
  const std::string dir =
      (std::filesystem::temp_directory_path() / "demfem_calibrate_seeds").string();
  std::filesystem::remove_all(dir);
  // With the loading-rate check at half rate (the later --set wins).
  const auto r = run_demfem(
      small(dir) + " --set Problem/seeds=2 --set \"Tests/loading rate check=half\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const json m  = read_json(dir + "/material.json");
  const json s0 = read_json(dir + "/seed_10000/material.json");
  const json s1 = read_json(dir + "/seed_10001/material.json");
  CHECK(m["seeds"] == json::array({10000, 10001}));
  for (const char *key : {"E", "nu", "ucs", "crack_initiation", "porosity"})
    {
      const double a = s0[key], b = s1[key];
      INFO(key << ": " << a << ", " << b);
      // Two different packings: different values (else the seeds did not
      // reach the genesis).
      CHECK(a != b);
      // Mean and sample standard deviation of two values: (a + b) / 2 and
      // |a - b| / sqrt(2), to round-off.
      CHECK(m[key].get<double>() == Approx(0.5 * (a + b)).epsilon(1e-12));
      CHECK(m["seed_scatter"][key].get<double>() ==
            Approx(std::abs(a - b) / std::sqrt(2.0)).epsilon(1e-9));
      CHECK(m["seed_values"][key] == json::array({a, b}));
    }
  // How well the means are known: the 95 % interval of two values is
  // t_{0.975, 1} s / sqrt(2) with t = 12.706205 (t tables), and a 5 %
  // standard error needs (s / mean / 0.05)^2 packings, rounded up.
  for (const char *key : {"E", "nu", "ucs"})
    {
      const double a = s0[key], b = s1[key];
      const double mean = 0.5 * (a + b), sd = std::abs(a - b) / std::sqrt(2.0);
      const json  &c = m["seed_confidence"][key];
      INFO(key << ": " << c.dump());
      CHECK(c["packings"] == 2);
      CHECK(c["half_width_95"].get<double>() ==
            Approx(12.706205 * sd / std::sqrt(2.0)).epsilon(1e-6));
      CHECK(c["relative_half_width_95"].get<double>() ==
            Approx(12.706205 * sd / std::sqrt(2.0) / std::abs(mean)).epsilon(1e-6));
      const double cov = sd / std::abs(mean);
      CHECK(c["packings_for_5_percent_standard_error"].get<double>() ==
            std::max(1.0, std::ceil(cov * cov / (0.05 * 0.05))));
    }
  CHECK_FALSE(m["seed_confidence"].contains("bts")); // not measured
  CHECK_THAT(r.out, Catch::Contains("packings for a 5 % standard error"));
  CHECK(m["ratios"]["crack_initiation_to_ucs"].get<double>() ==
        Approx(0.5 * (s0["ratios"]["crack_initiation_to_ucs"].get<double>() +
                      s1["ratios"]["crack_initiation_to_ucs"].get<double>()))
            .epsilon(1e-12));
  // The material itself is the first seed's (the genesis seed of a region
  // made from this file) with its test settings.
  CHECK(m["microparameters"] == s0["microparameters"]);
  CHECK(m["lab_tests"] == s0["lab_tests"]);
  CHECK(m["bts"].is_null()); // no Brazilian test run: null in every seed

  // The rate check on the seed means: the relative change of the mean peak
  // from the two packings' peaks at the full and at half rate (their
  // summary.json), with its standard error and a verdict.
  const json   u0   = read_json(dir + "/seed_10000/summary.json")["tests"]["ucs"];
  const json   u1   = read_json(dir + "/seed_10001/summary.json")["tests"]["ucs"];
  const double full = u0["peak_Pa"].get<double>() + u1["peak_Pa"].get<double>();
  const double half =
      u0["peak_half_rate_Pa"].get<double>() + u1["peak_half_rate_Pa"].get<double>();
  const json &rc = m["rate_check_on_seed_means"]["ucs"]["half_rate"];
  INFO(rc.dump());
  CHECK(rc["packings"] == 2);
  CHECK(rc["relative_change_of_the_mean"].get<double>() ==
        Approx((half - full) / full).epsilon(1e-12));
  CHECK(rc["standard_error"].get<double>() >= 0);
  CHECK(rc["critical_t"].get<double>() ==
        Approx(12.706205).epsilon(1e-6)); // t_{0.975, 1}
  const std::string verdict = rc["verdict"];
  CHECK((verdict == "moves" || verdict == "does not move" || verdict == "undecided"));
  CHECK_THAT(r.out, Catch::Contains("ucs at half rate, on the seed means"));
}

// Problem/seeds with --fit is the best material's packings
// (tests/apps/calibrate_fit_test.cc), no longer refused.
TEST_CASE("calibrate: Problem/seeds out of range is refused naming the key",
          "[calibrate][seeds][app]")
{
  const std::string dir =
      (std::filesystem::temp_directory_path() / "demfem_calibrate_seeds_bad").string();
  std::filesystem::remove_all(dir);
  for (const std::string &bad :
       {std::string(" --set Problem/seeds=0"), std::string(" --set Problem/seeds=101")})
    {
      const auto r = run_demfem(small(dir) + bad);
      INFO(bad << "\n" << r.out);
      CHECK(r.exit_code == 1);
      CHECK(r.out.find("seeds") != std::string::npos);
      CHECK_FALSE(std::filesystem::exists(dir + "/material.json"));
    }
}

TEST_CASE("calibrate: packings side by side give the one-at-a-time results bit for bit",
          "[calibrate][seeds][app]")
{
  // Three packings on two threads run two at a time, one thread each
  // (apps/parallel_packings.h; one worker takes two packings), on one
  // thread one after the other: every packing's material file, history
  // and the seed means must be the same bytes (the contact loop does not
  // depend on the thread count, docs/architecture.md "Threads and
  // determinism"; the packings share only the serialized HDF5 checkpoints).
  const auto        tmp  = std::filesystem::temp_directory_path();
  const std::string side = (tmp / "demfem_calibrate_seeds_side").string(),
                    one  = (tmp / "demfem_calibrate_seeds_one").string();
  std::filesystem::remove_all(side);
  std::filesystem::remove_all(one);
  const auto a = run_with_threads(small(side) + " --set Problem/seeds=3", 2);
  INFO(a.out);
  REQUIRE(a.exit_code == 0);
  CHECK_THAT(a.out, Catch::Contains("3 packings, 2 at a time (one thread each)"));
  // Each packing's lines are tagged with its seed, whole.
  CHECK_THAT(a.out, Catch::Contains("demfem calibrate: seed 10001: ucs: peak"));
  const auto b = run_with_threads(small(one) + " --set Problem/seeds=3", 1);
  INFO(b.out);
  REQUIRE(b.exit_code == 0);
  CHECK_THAT(b.out, !Catch::Contains("at a time"));
  auto bytes = [](const std::string &f) {
    std::ifstream      in(f, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  for (const std::string f :
       {"/material.json", "/seed_10000/material.json", "/seed_10001/material.json",
        "/seed_10002/material.json", "/seed_10002/history_ucs.csv"})
    {
      INFO(f);
      const std::string x = bytes(side + f);
      REQUIRE_FALSE(x.empty());
      CHECK(x == bytes(one + f));
    }
}
