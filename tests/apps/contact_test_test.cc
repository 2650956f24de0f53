// `demfem contact-test` reproduces every expected value of the flat-joint
// memo §2.1 (Eq. 53-66) through the DEM engine. Tolerance 1e-4 relative:
// the memo quotes 5 significant digits. "Other components ~0": below 1e-9
// of the main component (round-off of sums over elements).
#include "run_command.h"

#include <catch2/catch.hpp>

#include <cmath>

using demfem::testing::json_numbers;
using demfem::testing::run_demfem;

namespace
{
  void check_case(const std::string &args, const std::string &main_key, double expected)
  {
    INFO("demfem contact-test " << args);
    const auto r = run_demfem("contact-test " + args);
    REQUIRE(r.exit_code == 0);
    auto v = json_numbers(r.out);
    for (const char *k : {"Fn", "Fss", "Fst", "Mt", "Mbs", "Mbt"})
      REQUIRE(v.count(k) == 1);
    CHECK(v[main_key] == Approx(expected).epsilon(1e-4));
    for (const auto &[k, x] : v)
      if (k != main_key)
        {
          INFO(k << " = " << x);
          CHECK(std::abs(x) <= 1e-9 * std::abs(expected));
        }
  }
} // namespace

TEST_CASE("contact-test parallel bond matches the closed forms (memo Eq. 59-61)", "[contact-test]")
{
  check_case("--model parallelbond --dim 2 --case axial", "Fn", 2.3200e7);
  check_case("--model parallelbond --dim 3 --case axial", "Fn", 1.8221e5);
  check_case("--model parallelbond --dim 3 --case twist", "Mt", -1.9806e2);
  check_case("--model parallelbond --dim 2 --case bend", "Mbs", -7.7333e4);
  check_case("--model parallelbond --dim 3 --case bend", "Mbt", -4.5553e2);
}

TEST_CASE("contact-test flat joint matches memo Eq. 64-66", "[contact-test]")
{
  check_case("--model flatjoint --dim 2 --case axial", "Fn", 2.3200e7);
  check_case("--model flatjoint --dim 3 --case axial", "Fn", 1.8221e5);
  check_case("--model flatjoint --dim 2 --case bend", "Mbs", -7.7333e4);
  // 2D bending is exact for any Nr (exact integrals, memo Eq. 44-49).
  check_case("--model flatjoint --dim 2 --case bend --Nr 1", "Mbs", -7.7333e4);
  check_case("--model flatjoint --dim 2 --case bend --Nr 7", "Mbs", -7.7333e4);
  check_case("--model flatjoint --dim 3 --case twist --Nr 2 --Nal 8", "Mt", -1.8112e2);
  check_case("--model flatjoint --dim 3 --case twist --Nr 3 --Nal 16", "Mt", -1.9211e2);
  check_case("--model flatjoint --dim 3 --case twist --Nr 4 --Nal 24", "Mt", -1.9495e2);
  check_case("--model flatjoint --dim 3 --case bend --Nr 2 --Nal 8", "Mbt", -4.1657e2);
  check_case("--model flatjoint --dim 3 --case bend --Nr 3 --Nal 16", "Mbt", -4.4185e2);
  check_case("--model flatjoint --dim 3 --case bend --Nr 4 --Nal 24", "Mbt", -4.4838e2);
}

TEST_CASE("contact-test 3D flat joint converges to the closed form from below", "[contact-test]")
{
  double last_t = 0, last_b = 0;
  for (auto [nr, nal] : {std::pair{2, 8}, {3, 16}, {4, 24}, {6, 36}})
    {
      const std::string d = " --Nr " + std::to_string(nr) + " --Nal " + std::to_string(nal);
      auto t = json_numbers(run_demfem("contact-test --dim 3 --case twist" + d).out)["Mt"];
      auto b = json_numbers(run_demfem("contact-test --dim 3 --case bend" + d).out)["Mbt"];
      CHECK(std::abs(t) > last_t);
      CHECK(std::abs(b) > last_b);
      CHECK(std::abs(t) < 1.9806e2);
      CHECK(std::abs(b) < 4.5553e2);
      last_t = std::abs(t), last_b = std::abs(b);
    }
}

TEST_CASE("contact-test rejects invalid options with a clear message", "[contact-test]")
{
  auto r = run_demfem("contact-test --dim 4");
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.out, Catch::Contains("--dim"));
  r = run_demfem("contact-test --model hertz");
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.out, Catch::Contains("flatjoint"));
  r = run_demfem("contact-test --dim 2 --case twist");
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.out, Catch::Contains("3D"));
  r = run_demfem("contact-test --E -5");
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.out, Catch::Contains("--E"));
  r = run_demfem("contact-test --Nr 0");
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.out, Catch::Contains("--Nr"));
  r = run_demfem("contact-test --bogus 1");
  CHECK(r.exit_code != 0);
  CHECK(run_demfem("contact-test --help").exit_code == 0);
}
