// `demfem study` in breakable mode (compared with the full-DEM reference) and
// the sweep axes of the method choices and the stability map (coupling
// variant, scheme, relaxation, stiffness contrast).
#include <catch2/catch.hpp>

#include "run_command.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using demfem::testing::json_numbers;
using demfem::testing::run_demfem;
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

  // A CSV file as rows of named fields (a quoted last field is not split).
  std::vector<std::map<std::string, std::string>> table(const std::string &f)
  {
    std::vector<std::map<std::string, std::string>> rows;
    std::ifstream                                   in(f);
    std::string                                     line;
    std::vector<std::string>                        names;
    auto                                            split = [](const std::string &l) {
      std::vector<std::string> v;
      const auto               q = l.find('"');
      std::stringstream        ss(l.substr(0, q));
      for (std::string t; std::getline(ss, t, ',');)
        v.push_back(t);
      if (q != std::string::npos)
        v.push_back(l.substr(q));
      else if (!l.empty() && l.back() == ',')
        v.push_back("");
      return v;
    };
    if (std::getline(in, line))
      names = split(line);
    while (std::getline(in, line))
      {
        const auto                         v = split(line);
        std::map<std::string, std::string> r;
        for (std::size_t i = 0; i < names.size() && i < v.size(); ++i)
          r[names[i]] = v[i];
        rows.push_back(r);
      }
    return rows;
  }

  std::string dir(const std::string &name)
  {
    const auto d = std::filesystem::temp_directory_path() / ("demfem_study_" + name);
    std::filesystem::remove_all(d);
    return d.string();
  }
} // namespace

TEST_CASE("study: breakable mode, embedded runs against the full-DEM reference",
          "[study][breakable]")
{
  // apps/examples/study_breakable_2d.prm: a = 0.4 m, a/d = 4, reference
  // R = 8 a (about 3 500 grains), with sigma_yy = -65 MPa instead of the
  // example's -50 so that the damage zone (the cracks connected to the wall,
  // coupling/damage_zone.h) reaches beyond b = 2 a - 2 d. At -50 MPa this
  // packing's zone is 0.14 m deep and stays inside b = 2 a (three isolated
  // cracks lie at its boundary: not region_too_small). Measured at -65 MPa:
  // the reference 0.345 m, b = 5 a 0.367 m (+6 %), b = 2 a region_too_small
  // (15 of the zone's cracks at its coupling boundary; 12 with the former
  // 16.3 GPa continuum), -8 %.
  const std::string d = dir("breakable");
  const auto        r = run_study("study_breakable_2d.prm", d,
                                  "--set \"Study/region radius factors=5, 2\" --set "
                                         "\"Study/agreement tolerance=0.3\" --set "
                                         "\"Tunnel/in situ stress yy=-65e6\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);

  // The reference: finished, equilibrated, the membrane held the in-situ
  // stress within its tolerance, and it has a damage zone.
  const auto ref = json_numbers(read(d + "/reference_00/summary.json"));
  CHECK(read(d + "/reference_00/summary.json").find("\"equilibrated\": true") !=
        std::string::npos);
  CHECK(ref.at("servo_error_insitu") <= 0.02);
  CHECK(ref.at("n_particles") > 3000);
  const double ref_depth = ref.at("damage_zone_depth");
  REQUIRE(ref_depth > 0.1); // at least a grain diameter (0.1 m)

  const auto rows = table(d + "/study.csv");
  REQUIRE(rows.size() == 2);
  for (const auto &row : rows)
    {
      REQUIRE(row.at("status") == "stable");
      REQUIRE(row.at("equilibrated") == "yes");
      CHECK(row.at("breakable") == "yes");
      CHECK(std::stod(row.at("reference_depth_m")) == Approx(ref_depth).epsilon(1e-5));
      // The in-situ state of each run: the region's error against sigma0
      // within the example's 5 % tolerance, and the interface strain the
      // in-situ servo needed where it runs (an interface on the affine
      // path: the condensed scheme, or the slaved layer explicit). The
      // example's region is given by DEM region keys (no material file, no
      // crack-initiation stress): no elastic zone.
      CHECK(std::stod(row.at("in_situ_error")) <= 0.05);
      const bool servoed =
          row.at("scheme") == "condensed" ||
          (row.at("scheme") == "explicit" && row.at("variant") == "slaved-layer");
      CHECK(row.at("servo_interface_strain_rel").empty() == !servoed);
      CHECK(row.at("elastic_zone_key").empty());
      CHECK(row.at("elastic_zone_depth_m").empty());
    }
  // The largest region agrees with the reference on the damage-zone depth
  // within the scatter of one packing at a/d = 4, where the zone is about
  // two grain diameters deep and cracks sit at contacts, so the depth moves
  // in steps of about one diameter (0.1 m): eight seeds of this example
  // put single b = 5 a runs between -53 % and +31 % of their reference
  // at -50 MPa (docs/study.md). One seed is held to one grain diameter,
  // and the agreement tolerance is 0.3.
  const auto &big = rows[0];
  REQUIRE(std::stod(big.at("region_factor")) == Approx(5));
  CHECK(std::abs(std::stod(big.at("damage_zone_depth_m")) - ref_depth) <= 0.1);
  CHECK(big.at("agrees") == "yes");
  CHECK(big.at("region_too_small") == "no");
  // The region much smaller than the damage zone: its coupling boundary is
  // inside the damage zone, flagged, and so not agreeing whatever its depth.
  const auto &small = rows[1];
  CHECK(small.at("region_too_small") == "yes");
  CHECK(small.at("agrees") == "no");
  const auto small_summary = json_numbers(read(d + "/run_001/summary.json"));
  CHECK(small_summary.at("zone_cracks_near_interface") > 0);
  CHECK(small_summary.at("zone_cracks_near_interface") <=
        small_summary.at("cracks_near_interface"));

  // The speed-up table has the agreeing run; the embedded model is faster.
  const auto sp = table(d + "/study_speedup.csv");
  REQUIRE(sp.size() >= 1);
  CHECK(sp[0].at("run") == "0");
  CHECK(std::stod(sp[0].at("speedup")) > 1);
  CHECK(std::stod(sp[0].at("speedup")) ==
        Approx(std::stod(sp[0].at("reference_wall_time_s")) /
               std::stod(sp[0].at("wall_time_s")))
            .epsilon(1e-4));
  const auto s = json_numbers(read(d + "/summary.json"));
  CHECK(s.at("speedup_rows") >= 1);
  CHECK(s.at("region_factor_smallest_agreeing") == Approx(5));
  CHECK(read(d + "/study.md").find("| 0 | 5 |") != std::string::npos);
  CHECK(read(d + "/study_pareto.svg").find("full-DEM reference") != std::string::npos);
  for (const char *bad : {",nan", ",-nan", ",inf", ",-inf"})
    CHECK(read(d + "/study.csv").find(bad) == std::string::npos);
}

TEST_CASE("study: breakable mode in 3D, the slab against the plane-strain slab reference",
          "[study][breakable]")
{
  // apps/examples/tunnel_3d.prm (a = 0.6 m, -10/-20 MPa, slab three grains
  // thick) coarsened to a/d = 2 to keep the test cheap (b = 4 a: a region
  // of 3 a leaves too few grains between the tunnel and the slaved layer):
  // the reference is the 3D slab r <= 8 a of the same thickness in a
  // cylindrical membrane. The damage zone's link is 3 grain diameters
  // (Tunnel/damage link length), which the embedded run and the reference
  // both measure with.
  const std::string d = dir("breakable_3d");
  const auto        r = run_study("tunnel_3d.prm", d,
                                  "--set \"Study/breakable=true\" --set "
                                         "\"Study/grain resolutions=2\" --set "
                                         "\"Study/region radius factors=4\" --set "
                                         "\"Coupling/step limit=15000\" --set "
                                         "\"Tunnel/damage link length=3\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const std::string ref_text = read(d + "/reference_00/summary.json");
  const auto        ref      = json_numbers(ref_text);
  CHECK(ref.at("dimension") == 3);
  // the slab keeps the region's thickness in grain diameters (three)
  CHECK(ref.at("slab_thickness_m") == Approx(3 * 0.6 / 2).epsilon(1e-9));
  CHECK(ref_text.find("\"equilibrated\": true") != std::string::npos);
  CHECK(ref.at("servo_error_insitu") <= 0.02);
  CHECK(ref.at("unbreakable_band_bonds") > 0);
  CHECK(ref.at("cracks_near_boundary") == 0);
  CHECK(ref.at("genesis_steps") > 0);
  const auto rows = table(d + "/study.csv");
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].at("status") == "stable");
  CHECK(rows[0].at("breakable") == "yes");
  CHECK(std::stod(rows[0].at("reference_depth_m")) ==
        Approx(ref.at("damage_zone_depth")).epsilon(1e-5));
  for (const char *run : {"/reference_00", "/run_000"})
    {
      INFO(run);
      const auto damage =
          nlohmann::json::parse(read(d + run + "/summary.json"))["damage"];
      CHECK(damage["link_grain_diameters"].get<double>() == 3.0);
      // L = 3 d with d = 2 a / (a/d) / 2 = 0.3 m: the slab's a/d = 2.
      CHECK(damage["link_length_m"].get<double>() == Approx(3 * 0.3).epsilon(1e-9));
    }
  const auto s = json_numbers(read(d + "/summary.json"));
  CHECK(s.at("dimension") == 3);
  CHECK(read(d + "/summary.json").find("\"embedding\": \"slab\"") != std::string::npos);
}

TEST_CASE("study: several seeds give means with 95 % intervals, the region answer "
          "uses them, and the seed chart",
          "[study][breakable]")
{
  // Two packings of the breakable example at b/a = 4, condensed continuum.
  const std::string d = dir("breakable_seeds");
  const auto        r = run_study("study_breakable_2d.prm", d,
                                  "--set \"Study/region radius factors=4\" --set "
                                         "\"Study/schemes=condensed\" --set "
                                         "\"Study/seeds=10000,10001\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto rows = table(d + "/study.csv");
  REQUIRE(rows.size() == 2);
  // The interval of the two embedded depths, as the table must print it:
  // mean +- t_{0.975,1} s / sqrt(2), t = 12.7062 (two values: s / sqrt(2) is
  // half their difference).
  const double      a    = std::stod(rows[0].at("damage_zone_depth_m"));
  const double      b    = std::stod(rows[1].at("damage_zone_depth_m"));
  const double      mean = 0.5 * (a + b), half = 12.7062 * 0.5 * std::abs(a - b);
  const std::string md = read(d + "/study.md");
  INFO(md);
  const std::string prefix = "| 4 | 4 | wall-facets, condensed, 1, 0.8 | 2 | ";
  const auto        row    = md.find(prefix);
  REQUIRE(row != std::string::npos);
  std::stringstream cells(md.substr(row + prefix.size()));
  std::string       cell;
  std::getline(cells, cell, '|'); // "mean +- half"
  double      m = 0, h = 0;
  std::string pm;
  std::stringstream(cell) >> m >> pm >> h;
  CHECK(pm == "+-");
  CHECK(m == Approx(mean).epsilon(1e-5));
  // study.csv prints 6 significant digits: the depths (~0.19 m) to 5e-7 m,
  // so their difference (~2e-3 m) to about 5e-4 relative.
  CHECK(h == Approx(half).epsilon(1e-3));
  // The region answer is the interval rule, and the seed chart is written.
  CHECK(read(d + "/summary.json").find("\"region_factor_rule\": \"confidence\"") !=
        std::string::npos);
  const std::string svg = read(d + "/study_seeds.svg");
  CHECK(svg.find("95 % interval of the mean") != std::string::npos);
  // Two panels, depth and damaged area (agreement needs both): the setting
  // is drawn once in each.
  CHECK(svg.find("damage-zone depth: (mean - reference mean)") != std::string::npos);
  CHECK(svg.find("damaged area: (mean - reference mean)") != std::string::npos);
  const std::string point = "b/a=4 a/d=4 wall-facets condensed, 2 seeds";
  const auto        first = svg.find(point);
  REQUIRE(first != std::string::npos);
  CHECK(svg.find(point, first + 1) != std::string::npos);
  CHECK(svg.find("nan") == std::string::npos);

  // Each run directory says how `demfem tunnel` repeats it: the same grains
  // (the swept diameters to 17 digits), the same steps, the same damage to
  // the last digit (results do not depend on anything else; the study ran
  // from the build directory with the example's absolute path).
  std::string cmd = read(d + "/run_001/command.txt");
  INFO(cmd);
  REQUIRE(cmd.rfind("demfem tunnel ", 0) == 0);
  CHECK(cmd.find("'DEM region/seed=10001'") != std::string::npos);
  CHECK(cmd.find("'DEM region/breakable=true'") != std::string::npos);
  cmd.erase(0, std::string("demfem ").size());
  cmd.erase(cmd.find_last_not_of('\n') + 1);
  const auto again = run_demfem(cmd);
  INFO(again.out);
  REQUIRE(again.exit_code == 0);
  const auto run    = json_numbers(read(d + "/run_001/summary.json"));
  const auto repeat = json_numbers(read(d + "/run_001/repeat/summary.json"));
  for (const char *key : {"n_particles", "steps", "cracks_total", "damage_zone_depth",
                          "wall_convergence_mean", "damaged_area_m2"})
    CHECK(repeat.at(key) == run.at(key));
}

TEST_CASE("study: variant, scheme, relaxation and stiffness-contrast axes, invalid and "
          "unstable rows, no NaN",
          "[study]")
{
  // Elastic sweep of apps/examples/study_2d.prm (b = 2.5 a, a/d = 3) over
  // the new axes. Variants and schemes not implemented by the tunnel run
  // are 'invalid' rows (with the reason) today and run once they are; a
  // safety of 2 diverges for the explicit wall-facet scheme (measured limit
  // 1.5-1.6 on this packing, docs/study.md).
  const std::string d = dir("axes");
  const auto        r = run_study(
             "study_2d.prm", d,
             "--set \"Study/region radius factors=2.5\" --set \"Study/grain resolutions=3\" "
                    "--set \"Study/subcycles=1\" --set \"Study/timestep safety factors=0.8,2\" "
                    "--set \"Study/coupling variants=wall-facets,slaved-layer\" --set "
                    "\"Study/schemes=explicit,quasi-static\" --set \"Study/relaxation factors=1\" "
                    "--set \"Study/stiffness contrasts=1,3\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const std::string text = read(d + "/study.csv");
  for (const char *bad : {",nan", ",-nan", ",inf", ",-inf"})
    CHECK(text.find(bad) == std::string::npos);
  const auto rows = table(d + "/study.csv");
  REQUIRE(rows.size() == 16); // 2 variants x 2 schemes x 2 safeties x 2 contrasts
  std::map<double, double> error_explicit; // contrast -> error at safety 0.8
  for (const auto &row : rows)
    {
      const auto &st = row.at("status");
      CHECK((st == "stable" || st == "unstable" || st == "invalid"));
      if (st == "invalid")
        CHECK(row.at("diagnosis").size() > 2); // the reason is given
      if (row.at("variant") == "wall-facets" && row.at("scheme") == "explicit")
        {
          const double safety = std::stod(row.at("timestep_safety"));
          CHECK(st == (safety > 1 ? "unstable" : "stable"));
          if (st == "stable")
            {
              REQUIRE(row.at("equilibrated") == "yes");
              error_explicit[std::stod(row.at("stiffness_contrast"))] =
                  std::stod(row.at("error_rel"));
            }
          else
            CHECK(row.at("error_rel").empty());
        }
    }
  // A continuum 3x stiffer than the region holds the wall back: the
  // convergence falls short of Kirsch (taken with the material's E).
  REQUIRE(error_explicit.size() == 2);
  CHECK(error_explicit[3] < error_explicit[1] - 0.1);
  // The stability map per scheme.
  const auto s = json_numbers(read(d + "/summary.json"));
  CHECK(s.at("stability_explicit_timestep_safety_largest_stable") == Approx(0.8));
  CHECK(s.at("stability_explicit_timestep_safety_smallest_unstable") == Approx(2));
  CHECK(s.at("stability_explicit_stiffness_contrast_largest_stable") == Approx(3));
  CHECK(read(d + "/summary.json")
            .find("stability_quasi_static_subcycles_smallest_stable") !=
        std::string::npos);
}

TEST_CASE("study: bad values of the new Study keys stop before any output", "[study]")
{
  const std::string d    = dir("bad_axes");
  const std::string base = "study " + std::string(DEMFEM_SOURCE_DIR) +
                           "/apps/examples/study_2d.prm --set \"Problem/output "
                           "directory=" +
                           d + "\" ";
  for (const auto &[set, key] : std::vector<std::pair<std::string, std::string>>{
           {"Study/coupling variants=wall-facets,glue", "Study/coupling variants"},
           {"Study/schemes=implicit", "Study/schemes"},
           {"Study/relaxation factors=1,2", "Study/relaxation factors"},
           {"Study/stiffness contrasts=0", "Study/stiffness contrasts"},
           {"Study/reference radius factor=4", "Study/reference radius factor"}})
    {
      const auto r = run_demfem(base + "--set \"" + set + "\"");
      INFO(set << "\n" << r.out);
      CHECK(r.exit_code == 1);
      CHECK(r.out.find(key) != std::string::npos);
      CHECK(!std::filesystem::exists(d));
    }
}
