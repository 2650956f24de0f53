// `demfem study` (docs/architecture.md, "Speed-versus-accuracy study"): small
// sweeps of apps/examples/study_2d.prm (a = 0.4 m, hydrostatic 10 MPa, region b
// = 2.5 a, a few hundred grains), and of apps/examples/study_3d_slab.prm.
#include <catch2/catch.hpp>

#include "run_command.h"

#include <cmath>
#include <cstdlib> // setenv
#include <filesystem>
#include <fstream>
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
  const double p = 10e6, a = 0.4, G = 16.3e9 / (2 * 1.11);
  const double u_kirsch = p * a / (2 * G);
} // namespace

TEST_CASE("study: time-step safety beyond the limit is detected as unstable, no NaN",
          "[study]")
{
  // The explicit scheme is stable for safety < 1 (dt below the critical
  // step); 1.5 exceeds it by half, and the engine's energy-balance /
  // continuum-growth checks must stop the run. Subcycles 1 and 20: dt is
  // scaled by 1/k for the continuum, so both are stable at safety 0.8.
  const std::string d = dir("stability");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=2.5\" --set \"Study/grain resolutions=3\" "
                    "--set \"Study/subcycles=1,20\" --set \"Study/timestep safety factors=0.8,1.5\" "
                    "--set \"Study/schemes=explicit\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 5); // header + 2 x 2 runs
  // The material keys' region is packed in the run's own model: no genesis
  // steps beside `steps` (a material-file region's genesis would count here).
  REQUIRE(rows[0].size() > 36);
  CHECK(rows[0][36] == "genesis_steps");
  for (std::size_t i = 1; i < rows.size(); ++i)
    {
      CHECK(rows[i][36] == "0");
      const bool beyond = std::stod(rows[i][7]) > 1;
      CHECK(rows[i][8] == (beyond ? "unstable" : "stable"));
      // a stable run is flagged equilibrated exactly when its final
      // unbalanced ratio met Coupling/equilibrium ratio (1e-3)
      if (!beyond)
        CHECK((rows[i][17] == "yes") == (std::stod(rows[i][18]) <= 1e-3));
    }
  const std::string text = read(d + "/study.csv") + read(d + "/summary.json");
  CHECK(text.find("nan") == std::string::npos);
  CHECK(text.find("inf") == std::string::npos);
  const auto s = json_numbers(read(d + "/summary.json"));
  CHECK(s.at("timestep_safety_largest_stable") == Approx(0.8));
  CHECK(s.at("timestep_safety_smallest_unstable") == Approx(1.5));
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
  // (coupled_model.cc). k = 1 gives +2.3 %; k = 4 must stay within the
  // resolution error of this coarse region (measured +3.3 %; limit 10 %).
  const std::string d = dir("subcycled_slaved");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=2.5\" --set \"Study/grain resolutions=4\" "
                    "--set \"Study/coupling variants=slaved-layer\" --set \"Study/subcycles=4\" "
                    "--set \"Study/timestep safety factors=0.8\" --set \"Study/schemes=explicit\"");
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

TEST_CASE("study: the error against Kirsch falls as the grain resolution rises",
          "[study]")
{
  // b = 4 a, a/d = 3 and 5, two packings each. With ~3 grains per tunnel
  // radius the wall is a handful of grains and the mean wall convergence
  // depends on the packing by O(d/a) (measured -21 % and +9 %); at a/d = 5
  // both packings are within a few % (measured -1.5 % and +3.6 %). Single
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
  double err[2] = {0, 0};
  for (std::size_t i = 1; i < rows.size(); ++i)
    {
      REQUIRE(rows[i][8] == "stable");
      REQUIRE(rows[i][17] == "yes"); // equilibrated: the error is meaningful
      CHECK(std::stod(rows[i][18]) <= 1e-3);
      // the Kirsch column is the closed form p a / (2 G)
      CHECK(std::stod(rows[i][13]) == Approx(u_kirsch).epsilon(1e-5));
      err[std::stod(rows[i][4]) > 4] += std::abs(std::stod(rows[i][14])) / 2;
    }
  INFO("mean |error| a/d=3: " << err[0] << ", a/d=5: " << err[1]);
  CHECK(err[1] < 0.5 * err[0]);
  CHECK(err[1] < 0.05);
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
                    "--set \"Study/subcycles=1\" --set \"Study/timestep safety factors=0.8,1.5\" "
                    "--set \"Study/schemes=explicit,condensed\" "
                    "--set \"Study/relaxation factors=0.3,1\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 5); // header + 2 schemes x 2 safeties
  for (std::size_t i = 1; i < rows.size(); ++i)
    {
      CHECK(rows[i][21].empty()); // relaxation: not a setting of these schemes
      if (std::stod(rows[i][7]) < 1)
        {
          CHECK(rows[i][8] == "stable");
          CHECK(rows[i][17] == "yes");
          CHECK(std::abs(std::stod(rows[i][14])) < 0.05);
        }
    }
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

TEST_CASE("study: the 3D slab in the elastic mode against plane-strain Kirsch, the "
          "breakable mode refused in 3D",
          "[study][3d]")
{
  // apps/examples/study_3d_slab.prm with the condensed scheme only: b = 3 a,
  // a/d = 4, a slab 3 grains thick, about 1 250 spheres. The continuum has
  // the slab's measured constants, so Kirsch (p a / (2 G), G = 12.5e9 /
  // 2.2) is the answer up to the packing's O(d/a) noise at a/d = 4 (2D:
  // -21 % to +9 % at a/d = 3, within 4 % at 5); measured +3.4 % (explicit:
  // +3.3 %). The grains are scaled with a/d and the slab keeps its thickness
  // in grain diameters.
  setenv("OMP_NUM_THREADS", "1", 1);
  const std::string d = dir("slab3d");
  const auto r = run_study("study_3d_slab.prm", d, "--set \"Study/schemes=condensed\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = csv(d + "/study.csv");
  REQUIRE(rows.size() == 2);
  CHECK(rows[1][8] == "stable");
  CHECK(rows[1][17] == "yes");
  const double G = 12.5e9 / 2.2;
  CHECK(std::stod(rows[1][13]) == Approx(p * a / (2 * G)).epsilon(1e-5));
  CHECK(std::abs(std::stod(rows[1][14])) < 0.15);
  const std::string json = read(d + "/summary.json");
  CHECK(json.find("\"dimension\": 3") != std::string::npos);
  CHECK(json.find("\"embedding\": \"slab\"") != std::string::npos);

  // Breakable: the full-DEM reference is 2D; refused naming the key before
  // anything is written.
  const std::string d2 = dir("slab3d_breakable");
  const auto b = run_study("study_3d_slab.prm", d2, "--set \"Study/breakable=true\"");
  CHECK(b.exit_code == 1);
  CHECK(b.out.find("Study/breakable") != std::string::npos);
  CHECK(b.out.find("2D only") != std::string::npos);
  CHECK(!std::filesystem::exists(d2));
}
