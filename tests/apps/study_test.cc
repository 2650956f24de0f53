// `demfem study` (docs/architecture.md, "Speed-versus-accuracy study"): small
// sweeps of apps/examples/study_2d.prm (a = 0.4 m, hydrostatic 10 MPa, region b
// = 2.5 a, a few hundred grains), and of apps/examples/study_3d_slab.prm.
#include <catch2/catch.hpp>

#include "run_command.h"

#include <cmath>
#include <cstdlib> // setenv
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

using demfem::testing::json_numbers;
using demfem::testing::run_study;

namespace
{
  std::string read(const std::string &f)
  {
    std::ifstream     in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  // study.csv as rows of fields (the diagnosis, quoted, is the last field
  // and is not split).
  std::vector<std::vector<std::string>> csv(const std::string &f)
  {
    std::vector<std::vector<std::string>> rows;
    std::ifstream                         in(f);
    for (std::string line; std::getline(in, line);)
      {
        std::vector<std::string> row;
        const auto               q = line.find('"');
        std::stringstream        ss(line.substr(0, q));
        for (std::string t; std::getline(ss, t, ',');)
          row.push_back(t);
        rows.push_back(row);
      }
    return rows;
  }

  std::string dir(const std::string &name)
  {
    const auto d = std::filesystem::temp_directory_path() / ("demfem_study_" + name);
    std::filesystem::remove_all(d);
    return d.string();
  }

  // Kirsch mean wall convergence for hydrostatic p: u = p a / (2 G).
  const double p = 10e6, a = 0.4, G = 13.6e9 / (2 * 1.155);
  const double u_kirsch = p * a / (2 * G);
} // namespace

TEST_CASE("study: time-step safety beyond the limit is detected as unstable, no NaN",
          "[study]")
{
  // The critical-step estimate (sum of contact stiffnesses per grain) is
  // conservative: on this packing (a/d = 3, b = 2.5 a) the explicit scheme
  // is measured stable up to safety 1.5 (which ends marginal, unbalanced
  // ratio 0.01 at the step limit) and diverges from 1.6 (energy balance
  // broken at step 390; at 2 at step 120). Safety 2 is beyond the limit, and
  // the engine's energy-balance / continuum-growth checks must stop the run.
  // Subcycles 1 and 20: dt is scaled by 1/k for the continuum, so both are
  // stable at safety 0.8.
  const std::string d = dir("stability");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=2.5\" --set \"Study/grain resolutions=3\" "
                    "--set \"Study/subcycles=1,20\" --set \"Study/timestep safety factors=0.8,2\" "
                    "--set \"Study/schemes=explicit\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 5); // header + 2 x 2 runs
  // The region is packed by the calibration's genesis in a model of its
  // own: its steps are counted beside `steps`, not in them.
  // The four runs share one packing (docs/study.md, "Packing reuse"): the
  // first packs it, the others reuse it, and every run's wall time counts
  // the packing's.
  REQUIRE(rows[0].size() > 40);
  CHECK(rows[0][38] == "genesis_steps");
  CHECK(rows[0][39] == "genesis_reused");
  CHECK(rows[0][40] == "genesis_wall_time_s");
  for (std::size_t i = 1; i < rows.size(); ++i)
    {
      CHECK(std::stod(rows[i][38]) > 0);
      CHECK(rows[i][38] == rows[1][38]);
      CHECK(rows[i][39] == (i == 1 ? "no" : "yes"));
      CHECK(std::stod(rows[i][11]) >= std::stod(rows[i][40]));
      const bool beyond = std::stod(rows[i][7]) > 1;
      CHECK(rows[i][8] == (beyond ? "unstable" : "stable"));
      // a stable run is flagged equilibrated exactly when its final
      // unbalanced ratio met Coupling/equilibrium ratio (1e-3)
      if (!beyond)
        CHECK((rows[i][17] == "yes") == (std::stod(rows[i][18]) <= 1e-3));
    }
  // The in-situ error of every stable run; the explicit wall facets have
  // no in-situ servo (their interface does not follow the affine path), so
  // its column is empty; no elastic zone without a material file.
  REQUIRE(rows[0].size() > 48);
  CHECK(rows[0][45] == "in_situ_error");
  CHECK(rows[0][46] == "servo_interface_strain_rel");
  CHECK(rows[0][48] == "elastic_zone_depth_m");
  for (std::size_t i = 1; i < rows.size(); ++i)
    {
      const bool stable = rows[i][8] == "stable";
      CHECK(rows[i][45].empty() == !stable);
      if (stable)
        CHECK(std::stod(rows[i][45]) < 0.1);
      CHECK(rows[i][46].empty());
      CHECK(rows[i][48].empty());
    }
  const std::string text = read(d + "/study.csv") + read(d + "/summary.json");
  CHECK(text.find("nan") == std::string::npos);
  CHECK(text.find("inf") == std::string::npos);
  const auto s = json_numbers(read(d + "/summary.json"));
  CHECK(s.at("timestep_safety_largest_stable") == Approx(0.8));
  CHECK(s.at("timestep_safety_smallest_unstable") == Approx(2));
  CHECK(s.at("subcycles_largest_stable") == Approx(20));
  CHECK(s.at("unstable") == 2);
}

TEST_CASE("study: a sub-cycled slaved layer stays accurate (coupled window limit)",
          "[study][subcycles]")
{
  // Regression: the slaved layer at a/d = 4 with k = 4 settled, without any
  // divergence reported, into a wrong state (error -331 %, region stress
  // +200 MPa for -10 MPa) before the continuum window was limited by the
  // contacts hung on the coupling nodes and the window lag
  // (coupled_model.cc). k = 4 must stay within the resolution error of this
  // coarse region (limit 10 %). The continuum gets the slaved layer's own
  // plane-strain constants (E 15.0 GPa, nu 0.129, measured on this packing
  // by the anisotropic probe, docs/tunnel.md): study_2d.prm's are the wall
  // facets'. Measured -4.5 % at k = 1 and at k = 4.
  const std::string d = dir("subcycled_slaved");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=2.5\" --set \"Study/grain resolutions=4\" "
                    "--set \"Study/coupling variants=slaved-layer\" --set \"Study/subcycles=4\" "
                    "--set \"Study/timestep safety factors=0.8\" --set \"Study/schemes=explicit\" "
                    "--set \"Continuum/young modulus=15.0e9\" --set \"Continuum/poisson ratio=0.129\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 2);
  CHECK(rows[1][8] == "stable");
  CHECK(rows[1][17] == "yes");
  CHECK(std::abs(std::stod(rows[1][14])) < 0.10);
}

TEST_CASE("study: DEM region/radius = auto encloses the Kirsch damage zone", "[study]")
{
  // Hydrostatic p: sigma1 - sigma3 = 2 p a^2 / r^2 (Kirsch), so the zone
  // where it reaches 0.4 UCS ends at r* = a sqrt(2 p / (0.4 UCS)). UCS = 25
  // MPa: r* = a sqrt(2) = 0.5657 m; region = r* + 3 d, d = a / 4.
  const std::string d = dir("auto");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=auto\" --set \"Study/grain resolutions=4\" "
                    "--set \"Study/subcycles=1\" --set \"Study/timestep safety factors=0.8\" "
                    "--set \"Study/ucs=25e6\" --set \"Study/schemes=explicit\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto   s      = json_numbers(read(d + "/summary.json"));
  const double rstar  = a * std::sqrt(2 * p / (0.4 * 25e6));
  const double dgrain = a / 4;
  CHECK(s.at("auto_damage_threshold_Pa") == Approx(10e6));
  CHECK(s.at("auto_damage_radius_m") == Approx(rstar).epsilon(1e-6));
  CHECK(s.at("auto_region_radius_m") == Approx(rstar + 3 * dgrain).epsilon(1e-6));
  CHECK(s.at("auto_region_radius_m") > rstar + 2 * dgrain); // encloses zone + 2 grains
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 2);
  CHECK(rows[1][3] == "yes");
  CHECK(std::stod(rows[1][1]) == Approx(rstar + 3 * dgrain).epsilon(1e-5));
  CHECK(rows[1][8] == "stable");
  CHECK(r.out.find("damage zone") != std::string::npos); // the choice is printed
}

TEST_CASE("study: a bad sweep value is rejected naming the key, nothing written",
          "[study]")
{
  const std::string d = dir("bad");
  const auto r = run_study("study_2d.prm", d, "--set \"Study/grain resolutions=3,x\"");
  CHECK(r.exit_code == 1);
  CHECK(r.out.find("Study/grain resolutions") != std::string::npos);
  CHECK(!std::filesystem::exists(d));
}

TEST_CASE("study: the error against Kirsch stays within the packing scatter at a/d 3 "
          "and 5",
          "[study]")
{
  // b = 4 a, a/d = 3 and 5, two packings each. On the genesis packing the
  // wall convergence depends on the packing by up to 14 % at every a/d
  // tried, and the seed scatter does not fall with the resolution
  // (docs/study.md, "Accuracy against Kirsch on the genesis packing":
  // a/d 3: -13.8 % / -0.7 %, a/d 5: -8.6 % / -2.0 %, a/d 6: -1.7 % /
  // -11.7 %, a/d 8: -5.1 % / -14.0 %). Two biases of order d/a enter: the
  // measure averages grains whose centres lie up to d outside the wall
  // (Kirsch there is smaller by about d/(2a)), and the carved surface is
  // softer than the bulk. Limit 15 %: the measured scatter. Single
  // thread: the wall times of a loaded machine do not matter here.
  setenv("OMP_NUM_THREADS", "1", 1);
  const std::string d = dir("resolution");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=4\" --set \"Study/grain resolutions=3,5\" "
                    "--set \"Study/subcycles=1\" --set \"Study/timestep safety factors=0.8\" "
                    "--set \"Study/seeds=10000,777\" --set \"Study/schemes=explicit\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 5);
  for (std::size_t i = 1; i < rows.size(); ++i)
    {
      INFO("a/d " << rows[i][4] << ", seed " << rows[i][16] << ": error " << rows[i][14]);
      REQUIRE(rows[i][8] == "stable");
      REQUIRE(rows[i][17] == "yes"); // equilibrated: the error is meaningful
      CHECK(std::stod(rows[i][18]) <= 1e-3);
      // the Kirsch column is the closed form p a / (2 G)
      CHECK(std::stod(rows[i][13]) == Approx(u_kirsch).epsilon(1e-5));
      CHECK(std::abs(std::stod(rows[i][14])) < 0.15);
      // Kirsch where the wall grains are (hydrostatic: p a^2 / (2 G r)),
      // averaged over the grains of the run's wall_displacement.csv
      REQUIRE(rows[0].size() > 42);
      CHECK(rows[0][41] == "kirsch_at_grains_m");
      std::ostringstream run;
      run << d << "/run_" << std::setw(3) << std::setfill('0') << rows[i][0]
          << "/wall_displacement.csv";
      const auto wall = csv(run.str());
      REQUIRE(wall.size() > 10);
      double u_at = 0;
      for (std::size_t k = 1; k < wall.size(); ++k)
        u_at += p * a * a /
                (2 * G * std::hypot(std::stod(wall[k][0]), std::stod(wall[k][1])));
      u_at /= double(wall.size() - 1);
      // (study.csv prints 6 significant digits: 5e-6 relative per value)
      CHECK(std::stod(rows[i][41]) == Approx(u_at).epsilon(1e-5));
      CHECK(u_at < u_kirsch); // the grains' centres lie outside the wall
      const double u = std::stod(rows[i][12]);
      CHECK(std::stod(rows[i][42]) == Approx((u - u_at) / u_at).margin(3e-5));
    }
}

TEST_CASE("study: the explicit and condensed schemes side by side: stability map per "
          "scheme, chart legend, no relaxation axis",
          "[study][schemes]")
{
  // Two schemes, two safeties and two relaxations: the relaxation is a
  // setting of the quasi-static scheme only, so each of these schemes runs
  // once per safety (4 runs, not 8), its study.csv relaxation is empty and
  // the map has no relaxation key; the condensed scheme gets its own map.
  setenv("OMP_NUM_THREADS", "1", 1);
  const std::string d = dir("schemes");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=2.5\" --set \"Study/grain resolutions=3\" "
                    "--set \"Study/subcycles=1\" --set \"Study/timestep safety factors=0.8,2\" "
                    "--set \"Study/schemes=explicit,condensed\" "
                    "--set \"Study/relaxation factors=0.3,1\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 5); // header + 2 schemes x 2 safeties
  std::vector<double> convergence;
  for (std::size_t i = 1; i < rows.size(); ++i)
    {
      CHECK(rows[i][21].empty()); // relaxation: not a setting of these schemes
      if (std::stod(rows[i][7]) < 1)
        {
          CHECK(rows[i][8] == "stable");
          CHECK(rows[i][17] == "yes");
          // a/d = 3: the packing scatter (15 %, see the resolution test);
          // measured +7.6 % (explicit), +6.8 % (condensed)
          CHECK(std::abs(std::stod(rows[i][14])) < 0.15);
          convergence.push_back(std::stod(rows[i][12]));
        }
    }
  // On the same packing the two schemes reach the same equilibrium; they
  // differ by what each one's equilibrium criterion leaves (final
  // unbalanced ratios 2e-5 and 3e-4 against the 1e-3 target): measured
  // 0.8 %, limit 2 %.
  REQUIRE(convergence.size() == 2);
  CHECK(convergence[1] == Approx(convergence[0]).epsilon(0.02));
  const std::string json = read(d + "/summary.json");
  const auto        s    = json_numbers(json);
  CHECK(s.at("stability_condensed_timestep_safety_largest_stable") == Approx(0.8));
  CHECK(s.at("stability_explicit_timestep_safety_largest_stable") == Approx(0.8));
  CHECK(json.find("relaxation") == std::string::npos);
  // The chart tells the schemes apart: a legend entry per scheme and the
  // condensed runs drawn as triangles.
  const std::string svg = read(d + "/study_pareto.svg");
  CHECK(svg.find(">explicit: ") != std::string::npos);
  CHECK(svg.find(">condensed: ") != std::string::npos);
  CHECK(svg.find("<polygon") != std::string::npos);
  CHECK(svg.find("nan") == std::string::npos);
}

TEST_CASE("study: the quasi-static map counts larger subcycles as the safe side",
          "[study][schemes]")
{
  // The quasi-static iteration diverges at k = 1 (the DEM cannot respond
  // within one step) and converges at k = 200 (docs/tunnel.md). Its
  // subcycles limits read from the large side, and the relaxation is mapped
  // at k = 200, not at the diverging k = 1.
  setenv("OMP_NUM_THREADS", "1", 1);
  const std::string d = dir("quasi_static_map");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=2.5\" --set \"Study/grain resolutions=3\" "
                    "--set \"Study/subcycles=1,200\" --set \"Study/timestep safety factors=0.8\" "
                    "--set \"Study/schemes=quasi-static\" --set \"Study/relaxation factors=0.3\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 3);
  const auto s = json_numbers(read(d + "/summary.json"));
  CHECK(s.at("stability_quasi_static_subcycles_smallest_stable") == Approx(200));
  CHECK(s.at("stability_quasi_static_subcycles_largest_unstable") == Approx(1));
  CHECK(s.at("stability_quasi_static_relaxation_largest_stable") == Approx(0.3));
}

TEST_CASE("study: the 3D slab in the elastic mode against plane-strain Kirsch",
          "[study][3d]")
{
  // apps/examples/study_3d_slab.prm with the condensed scheme only: b = 3 a,
  // a/d = 4, a slab 3 grains thick, about 1 250 spheres. The continuum has
  // the slab's measured constants, so Kirsch (p a / (2 G), G = 11.4e9 /
  // 2.22) is the answer up to the packing's O(d/a) noise at a/d = 4 (2D:
  // -21 % to +9 % at a/d = 3, within 4 % at 5); measured 5.0 % on the genesis
  // packing (the former packing: +3.4 %, explicit +3.3 %). The grains are scaled with a/d
  // and the slab keeps its thickness in grain diameters.
  setenv("OMP_NUM_THREADS", "1", 1);
  const std::string d = dir("slab3d");
  const auto r = run_study("study_3d_slab.prm", d, "--set \"Study/schemes=condensed\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 2);
  CHECK(rows[1][8] == "stable");
  CHECK(rows[1][17] == "yes");
  const double G = 11.4e9 / 2.22;
  CHECK(std::stod(rows[1][13]) == Approx(p * a / (2 * G)).epsilon(1e-5));
  CHECK(std::abs(std::stod(rows[1][14])) < 0.15);
  const std::string json = read(d + "/summary.json");
  CHECK(json.find("\"dimension\": 3") != std::string::npos);
  CHECK(json.find("\"embedding\": \"slab\"") != std::string::npos);
  // The breakable mode in 3D (against the 3D slab reference):
  // study_breakable_test.cc.
}
