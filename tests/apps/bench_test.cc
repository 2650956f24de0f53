// `demfem bench dem` (docs/bench.md): output contract and option checking.
// No timing assertions: the benchmark's speed depends on the machine.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <regex>
#include <string>

namespace
{
  struct RunResult
  {
    std::string out;
    int         status = -1;
  };

  /// Runs the demfem executable with `args` (stderr merged into the output).
  RunResult run_demfem(const std::string &args)
  {
    RunResult         r;
    const std::string cmd = std::string("\"") + DEMFEM_EXE + "\" " + args + " 2>&1";
    FILE             *f   = popen(cmd.c_str(), "r");
    REQUIRE(f != nullptr);
    char buf[4096];
    while (std::fgets(buf, sizeof buf, f))
      r.out += buf;
    const int st = pclose(f);
    r.status     = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
  }

  /// Numeric value of "key": number in a flat JSON object (NaN if absent).
  double json_number(const std::string &json, const std::string &key)
  {
    const std::regex re("\"" + key + "\"\\s*:\\s*([-+0-9.eE]+)");
    std::smatch      m;
    if (!std::regex_search(json, m, re))
      return std::nan("");
    return std::stod(m[1].str());
  }
} // namespace

TEST_CASE("bench dem --json reports the run of a dense bonded assembly", "[bench]")
{
  const RunResult r =
      run_demfem("bench dem --dim 2 --n 500 --steps 20 --threads 1 --json");
  INFO(r.out);
  REQUIRE(r.status == 0);
  for (const char *key :
       {"dim", "n_particles", "n_contacts", "threads", "steps", "wall_s",
        "particle_steps_per_s", "contact_updates_per_s", "setup_s", "timestep"})
    {
      INFO(key);
      CHECK(std::isfinite(json_number(r.out, key)));
    }
  CHECK(json_number(r.out, "dim") == 2);
  CHECK(json_number(r.out, "n_particles") == 500);
  CHECK(json_number(r.out, "threads") == 1);
  CHECK(json_number(r.out, "steps") == 20);
  // Dense and bonded: a hexagonal lattice bonds ~72% of its 3 neighbour
  // pairs per grain, so contacts clearly exceed grains.
  CHECK(json_number(r.out, "n_contacts") > 500);
  CHECK(json_number(r.out, "wall_s") > 0);
  CHECK(json_number(r.out, "timestep") > 0);
  // Throughput is derived from the counts and the wall time.
  CHECK(json_number(r.out, "particle_steps_per_s") ==
        Approx(500 * 20 / json_number(r.out, "wall_s")).epsilon(1e-4));
}

TEST_CASE("bench dem rejects invalid options naming them", "[bench]")
{
  const RunResult dim = run_demfem("bench dem --dim 4 --n 500 --steps 20");
  CHECK(dim.status != 0);
  CHECK_THAT(dim.out, Catch::Contains("--dim"));
  const RunResult thr = run_demfem("bench --dim 2 --threads 0");
  CHECK(thr.status != 0);
  CHECK_THAT(thr.out, Catch::Contains("--threads"));
  const RunResult unk = run_demfem("bench dem --bogus 1");
  CHECK(unk.status != 0);
  CHECK_THAT(unk.out, Catch::Contains("--bogus"));
  const RunResult help = run_demfem("bench --help");
  CHECK(help.status == 0);
  CHECK_THAT(help.out, Catch::Contains("--steps"));
}

TEST_CASE("bench dem --material builds the scene of a material file", "[bench]")
{
  const std::string ldb =
      std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/lac_du_bonnet_2d.material.json";
  const RunResult r = run_demfem("bench dem --material " + ldb +
                                 " --n 500 --steps 20 --threads 1 --json");
  INFO(r.out);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("lac_du_bonnet_2d.material.json"));
  CHECK(json_number(r.out, "dim") == 2); // from the file
  CHECK(json_number(r.out, "n_particles") == 500);
  // The LdB material's joints: bonded, fj_B = 0.925, and slit, fj_S =
  // 0.075, none gapped; the genesis bonds round(B n) of the n joints
  // (designate_microstructure, dem/specimen/property_rules.cc), so the slit
  // count is S n to half a joint.
  const double n_fj = json_number(r.out, "n_flatjoints");
  CHECK(json_number(r.out, "n_bonded") + json_number(r.out, "n_slit") == n_fj);
  CHECK(json_number(r.out, "n_gapped") == 0);
  CHECK(std::abs(json_number(r.out, "n_slit") - 0.075 * n_fj) <= 0.51);
  CHECK(json_number(r.out, "n_flatjoints") > 500);
  // Elements per joint from the file (fj_Nr = 2 in 2D).
  CHECK(json_number(r.out, "elements_per_contact") == 2);

  // A dimension that contradicts the file, a missing file, another law:
  // refused, naming what is wrong.
  const RunResult dim = run_demfem("bench dem --material " + ldb + " --dim 3 --n 500");
  CHECK(dim.status == 1);
  CHECK_THAT(dim.out, Catch::Contains("--dim 3"));
  const RunResult none = run_demfem("bench dem --material /nonexistent.json --n 500");
  CHECK(none.status == 1);
  CHECK_THAT(none.out, Catch::Contains("/nonexistent.json"));
  const RunResult arg = run_demfem("bench dem --material");
  CHECK(arg.status == 2);
  CHECK_THAT(arg.out, Catch::Contains("--material"));
}

TEST_CASE("bench voronoi compares the Voronoi models with the flat joint",
          "[bench][voronoi]")
{
  const RunResult r = run_demfem("bench voronoi --n 400 --steps 20 --threads 1 --json");
  INFO(r.out);
  REQUIRE(r.status == 0);
  const double fj  = json_number(r.out, "flatjoint_s_per_grain_step");
  const double vor = json_number(r.out, "rigid_voronoi_s_per_grain_step");
  CHECK(fj > 0);
  CHECK(vor > 0);
  // The ratio is the two costs' (no timing assertion: only consistency).
  CHECK(json_number(r.out, "rigid_voronoi_over_flatjoint_cost") ==
        Approx(vor / fj).epsilon(1e-9));
  const double flex = json_number(r.out, "flexible_voronoi_s_per_grain_step");
  CHECK(flex > 0);
  CHECK(json_number(r.out, "flexible_voronoi_over_flatjoint_cost") ==
        Approx(flex / fj).epsilon(1e-9));
  // The flexible grains' elements bound their step below the rigid one.
  CHECK(json_number(r.out, "flexible_voronoi_time_step_s") > 0);
  CHECK(json_number(r.out, "flexible_voronoi_time_step_s") <
        json_number(r.out, "rigid_voronoi_time_step_s"));
  CHECK(json_number(r.out, "n") == 400);
  // 2D only, its own scenes.
  for (const char *bad : {"bench voronoi --dim 3", "bench voronoi --material x.json"})
    {
      const RunResult b = run_demfem(bad);
      INFO(bad << "\n" << b.out);
      CHECK(b.status == 2);
      CHECK(b.out.find("demfem bench voronoi is 2D") != std::string::npos);
    }
}
