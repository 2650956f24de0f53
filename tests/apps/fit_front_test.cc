// `demfem calibrate FILE.prm --front FIT.csv` (docs/calibrate.md, "Which
// targets conflict"): an earlier fit's log against the file's Fit/Targets,
// into fit_front.{csv,json,svg}; no test runs. A hand-made log checks the
// columns read by name, the row with an error left out and the numbers; the
// committed 2D fit log checks the conflict docs/calibrate_ldb.md reports;
// bad input is refused naming the key or the file.
#include "run_command.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;
using demfem::testing::run_demfem;

namespace
{
  fs::path work_dir()
  {
    static const fs::path d =
        fs::temp_directory_path() / ("demfem_front_test_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }

  fs::path write(const std::string &name, const std::string &text)
  {
    const fs::path p = work_dir() / name;
    std::ofstream(p) << text;
    return p;
  }

  std::string read(const fs::path &p) { return demfem::testing::read_text(p.string()); }

  // The committed 2D example with a Fit/Targets subsection (`targets`: "set
  // key = value, weight, tolerance" lines), and the command-line options that
  // put its output into `out`.
  std::string prm(const std::string &name, const fs::path &out,
                  const std::string &targets)
  {
    const fs::path p = write(
        name,
        read(std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/lac_du_bonnet_2d.prm") +
            "\nsubsection Fit\n  subsection Targets\n" + targets + "  end\nend\n");
    return p.string() + " --set \"Problem/output directory=" + out.string() + "\"";
  }

  const std::string ucs_bts =
      "    set ucs = 200e6, 1, 0.05\n    set bts = 8.8e6, 1, 0.05\n";

  // Relative errors (tolerances, 5 % each): 1: UCS 0, BTS +13.6 % (2.73);
  // 2: UCS +20 % (4), BTS 0; 3: UCS +6 % (1.2), BTS +7.95 % (1.59);
  // 4: a failed measurement (error cell), left out.
  const std::string log_text =
      "evaluation,stage,tensile_strength_mean,ucs_mean,ucs_sd,bts_mean,bts_sd,"
      "objective,all_within_tolerance,seconds,error,note\n"
      "1,all,30e6,200e6,1e6,10e6,1e6,7.4,0,12,,\n"
      "2,all,40e6,240e6,1e6,8.8e6,1e6,16,0,12,,a note\n"
      "3,all,35e6,212e6,1e6,9.5e6,1e6,3.9,0,12,,\n"
      "4,all,36e6,,,,,1e300,0,3,the packing failed,\n";
} // namespace

TEST_CASE("calibrate --front finds the conflict in a fit's log", "[calibrate][front]")
{
  const fs::path out = work_dir() / "front";
  fs::remove_all(out);
  const fs::path log = write("fit.csv", log_text);
  const auto r = run_demfem("calibrate " + prm("front.prm", out, ucs_bts) + " --front " +
                            log.string());
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("ucs and bts conflict: each within tolerance alone (evaluations 1, "
                   "2), never together (closest: evaluation 3") != std::string::npos);
  const auto j = nlohmann::json::parse(read(out / "fit_front.json"));
  CHECK(j["evaluations"] == 3); // the failed row is left out
  REQUIRE(j["pairs"].size() == 1);
  const auto &p = j["pairs"][0];
  CHECK(p["target_a"] == "ucs");
  CHECK(p["target_b"] == "bts");
  CHECK(p["conflict"] == "yes");
  CHECK(p["evaluation_joint"] == 3);
  // max(|212 - 200| / 200, |9.5 - 8.8| / 8.8) / 0.05: round-off of one
  // division of doubles read from decimal text.
  CHECK(p["best_joint"].get<double>() == Approx(0.7 / 8.8 / 0.05).epsilon(1e-12));
  CHECK(p["joint_excess"].get<double>() == Approx(0.7 / 8.8 / 0.05).epsilon(1e-12));
  CHECK(p["front"] == nlohmann::json::array({1, 3, 2}));
  const std::string csv = read(out / "fit_front.csv");
  CHECK(csv.rfind("target_a,target_b,evaluations,best_a,evaluation_a,best_b,", 0) == 0);
  CHECK(csv.find("\nucs,bts,3,0,1,0,2,") != std::string::npos);
  CHECK(csv.find(",yes,1 3 2\n") != std::string::npos);
  // The CSV rows are the JSON records written cell by cell: a number to 17
  // digits reads back as the same double.
  std::istringstream rows(csv);
  std::string        header, row, cell;
  std::getline(rows, header);
  std::getline(rows, row);
  std::vector<std::string> cells;
  for (std::istringstream in(row); std::getline(in, cell, ',');)
    cells.push_back(cell);
  REQUIRE(cells.size() == 12);
  CHECK(std::stod(cells[7]) == p["best_joint"].get<double>());
  const std::string levers = read(out / "fit_levers.csv");
  CHECK(levers.rfind("parameter,target,pairs,change_per_range,largest_step,"
                     "change_at_largest_step,seed_sd\n",
                     0) == 0);
  CHECK(std::count(levers.begin(), levers.end(), '\n') == 1 + long(j["levers"].size()));
  CHECK(read(out / "fit_front.svg").find("<svg") != std::string::npos);
  CHECK(nlohmann::json::parse(read(out / "manifest.json"))["status"] == "ok");
}

TEST_CASE("calibrate --front on the committed 2D fit log: UCS and BTS conflict",
          "[calibrate][front]")
{
  // docs/calibrate_ldb.md, "Which targets conflict": the 50 evaluations of
  // the slits-and-gap fit (one packing each).
  const fs::path out = work_dir() / "committed";
  fs::remove_all(out);
  const std::string data = std::string(DEMFEM_SOURCE_DIR) + "/docs/data/";
  const auto        r =
      run_demfem("calibrate " + data + "ldb_2d_fit_slits_gap.prm --front " + data +
                 "ldb_2d_fit_slits_gap.csv --set \"Problem/output "
                 "directory=" +
                 out.string() + "\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(read(out / "fit_front.json"));
  CHECK(j["evaluations"] == 50);
  const auto &top = j["pairs"][0];
  CHECK(top["target_a"] == "ucs");
  CHECK(top["target_b"] == "bts");
  CHECK(top["conflict"] == "yes");
  CHECK(top["evaluation_a"] == 46);
  CHECK(top["evaluation_b"] == 4);
  CHECK(top["evaluation_joint"] == 34);
  // The logged measurements carry 17 digits: the analysis reproduces the
  // documented 1.191 tolerances to its printed digits.
  CHECK(top["best_joint"].get<double>() == Approx(1.191).margin(5e-4));
  CHECK(j["pairs"][1]["target_a"] == "nu");
  CHECK(j["pairs"][1]["target_b"] == "ucs");
  CHECK(j["pairs"][1]["conflict"] == "yes");
  int conflicts = 0;
  for (const auto &p : j["pairs"])
    conflicts += p["conflict"] == "yes";
  CHECK(conflicts == 2);
  CHECK(j["targets"][5]["target"] == "crack initiation ratio");
  CHECK(j["targets"][5]["reached"] == "no");

  // The third fit (three packings per evaluation): its first 13
  // evaluations are BOBYQA's one-at-a-time model, so every searched
  // parameter has three pairs; the levers docs/calibrate_ldb.md quotes.
  const fs::path out3 = work_dir() / "committed_3seeds";
  fs::remove_all(out3);
  const auto r3 = run_demfem(
      "calibrate " + data + "ldb_2d_fit_3seeds.prm --front " + data +
      "ldb_2d_fit_3seeds.csv --set \"Problem/output directory=" + out3.string() + "\"");
  INFO(r3.out);
  REQUIRE(r3.exit_code == 0);
  const auto j3 = nlohmann::json::parse(read(out3 / "fit_front.json"));
  CHECK(j3["pairs"][0]["conflict"] == "no"); // nu is met in no evaluation
  std::map<std::string, double> lever;
  for (const auto &l : j3["levers"])
    {
      CHECK(l["pairs"] == 3);
      lever[l["parameter"].get<std::string>() + "/" + l["target"].get<std::string>()] =
          l["change_per_range"].get<double>();
    }
  CHECK(lever.size() == 36); // 6 parameters x 6 targets
  // Printed digits of the documented table.
  CHECK(lever["tensile strength mean/direct tension"] == Approx(1.371).margin(5e-4));
  CHECK(lever["tensile strength sd/direct tension"] == Approx(-0.707).margin(5e-4));
  CHECK(lever["cohesion mean/direct tension"] == 0); // c leaves DT to the digit
  CHECK(fs::is_regular_file(out3 / "fit_levers.csv"));
}

TEST_CASE("calibrate --front refuses bad input naming the key or the file",
          "[calibrate][front]")
{
  const fs::path out = work_dir() / "bad";
  fs::remove_all(out);
  const fs::path log = write("fit_bad.csv", log_text);
  // A target the log did not measure.
  auto r = run_demfem("calibrate " +
                      prm("dt.prm", out, ucs_bts + "    set direct tension = 6.9e6\n") +
                      " --front " + log.string());
  CHECK(r.exit_code == 1);
  CHECK(r.out.find("no column 'direct_tension_mean'") != std::string::npos);
  CHECK(r.out.find(log.string()) != std::string::npos);
  CHECK_FALSE(fs::exists(out / "fit_front.csv"));
  // One target: nothing to compare.
  r = run_demfem("calibrate " + prm("one.prm", out, "    set ucs = 200e6\n") +
                 " --front " + log.string());
  CHECK(r.exit_code == 1);
  CHECK(r.out.find("Fit/Targets: --front needs at least two targets") !=
        std::string::npos);
  // Not with --fit; and a log that cannot be read.
  r = run_demfem("calibrate " + prm("both.prm", out, ucs_bts) + " --fit --front " +
                 log.string());
  CHECK(r.exit_code == 1);
  CHECK(r.out.find("not with --fit") != std::string::npos);
  r = run_demfem("calibrate " + prm("none.prm", out, ucs_bts) + " --front " +
                 (work_dir() / "absent.csv").string());
  CHECK(r.exit_code == 1);
  CHECK(r.out.find("absent.csv: cannot be read") != std::string::npos);
  // The log inside the output directory: refused (--overwrite would
  // delete it with the directory's earlier results).
  r = run_demfem("calibrate " + prm("inside.prm", work_dir(), ucs_bts) + " --front " +
                 log.string() + " --overwrite");
  CHECK(r.exit_code == 1);
  CHECK(r.out.find("holds the log") != std::string::npos);
  CHECK(fs::is_regular_file(log));
  // A damaged row names its line.
  r = run_demfem("calibrate " + prm("damaged.prm", out, ucs_bts) + " --front " +
                 write("damaged.csv", log_text + "5,all,1\n").string());
  CHECK(r.exit_code == 1);
  CHECK(r.out.find("line 6: 3 cells") != std::string::npos);
}
