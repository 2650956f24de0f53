// `demfem calibrate --fit` (docs/calibrate.md, "Automatic calibration"): on a
// tiny, cheap problem the fit recovers known microparameters from the
// properties they produce; bad targets and empty search spaces are refused
// naming the key, before anything is written.
#include "run_command.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using demfem::testing::run_demfem;

namespace
{
  fs::path work_dir()
  {
    static const fs::path d =
        fs::temp_directory_path() / ("demfem_fit_test_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }

  // About 150 grains with unbreakable joints, loaded to an axial strain of
  // 1e-3: the elastic stage's small-strain test and the full UCS test are
  // then the same test, so E and nu are one deterministic function of
  // (E*, kappa*) on the fixed packing.
  std::string prm(const fs::path &out, double emod, double krat, const std::string &fit)
  {
    std::ostringstream s;
    s << "subsection Problem\n  set dimension = 2\n  set output directory = "
      << out.string() << "\n  set vtk = false\nend\n"
      << "subsection Material\n  set type = flatjointed\n"
         "  set size distribution = uniform 1.0e-3 1.6e-3 1\n"
         "  set number of grains = 150\n  set linear effective modulus = 40e9\n"
      << "  set effective modulus = " << emod << "\n  set stiffness ratio = " << krat
      << "\n  set friction = 0.6\n"
         "  subsection Flat joint\n    set tensile strength mean = 1e12\n"
         "    set cohesion mean = 1e12\n    set friction angle = 30\n  end\nend\n"
         "subsection Vessel\n  set height = 0.03\n  set width = 0.015\nend\n"
         "subsection Packing\n  set material pressure = 1e5\nend\n"
         "subsection Tests\n  set tests = ucs\n  set strain rate = 2\n"
         "  set strain limit = 1e-3\n  set history interval = 10\nend\n"
         "subsection Fit\n  set seeds = 1\n  set elastic strain = 1e-3\n"
      << fit << "end\n";
    return s.str();
  }

  fs::path write(const std::string &name, const std::string &text)
  {
    const fs::path p = work_dir() / name;
    std::ofstream(p) << text;
    return p;
  }

  std::string read(const fs::path &p) { return demfem::testing::read_text(p.string()); }

  // The rows of fit.csv, each split into its cells (a trailing empty
  // cell, the note, kept).
  std::vector<std::vector<std::string>> csv_rows(const fs::path &csv)
  {
    std::vector<std::vector<std::string>> out;
    std::istringstream                    in(read(csv));
    for (std::string line; std::getline(in, line);)
      {
        std::vector<std::string> c;
        std::stringstream        s(line);
        for (std::string x; std::getline(s, x, ',');)
          c.push_back(x);
        if (!line.empty() && line.back() == ',')
          c.push_back("");
        out.push_back(c);
      }
    return out;
  }

  // `demfem calibrate` of the material above (E* 40 GPa, kappa* 2) with
  // the Fit lines `fit` and the extra arguments `args`, into
  // work_dir()/name: that directory and the run.
  std::pair<fs::path, demfem::testing::CommandResult> calibrate_in(
      const std::string &name, const std::string &fit, const std::string &args)
  {
    const fs::path out = work_dir() / name;
    fs::remove_all(out);
    return {out,
            run_demfem("calibrate " +
                       write(name + ".prm", prm(out, 40e9, 2, fit)).string() + args)};
  }
} // namespace

TEST_CASE("calibrate --fit recovers known microparameters", "[calibrate][fit]")
{
  // 1. The properties of the known material E* = 40 GPa, kappa* = 2: one
  //    evaluation at the start point (fit.csv row 1), targets unreachable.
  const std::string search = "  set parameters = effective modulus 10e9 100e9; "
                             "stiffness ratio 1 4\n";
  const fs::path    out1   = work_dir() / "known";
  fs::remove_all(out1);
  const auto r1 = run_demfem(
      "calibrate " +
      write("known.prm", prm(out1, 40e9, 2,
                             search + "  set evaluations = 1\n  subsection Targets\n"
                                      "    set E = 1e9\n  end\n"))
          .string() +
      " --fit");
  INFO(r1.out);
  REQUIRE(r1.exit_code == 3); // honest: the dummy target was not reached
  std::istringstream csv(read(out1 / "fit.csv"));
  std::string        header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  REQUIRE(header.rfind("evaluation,stage,effective_modulus,stiffness_ratio,E_mean,E_sd",
                       0) == 0);
  std::vector<std::string> cells;
  for (std::stringstream r(row); r.good();)
    {
      std::string c;
      std::getline(r, c, ',');
      cells.push_back(c);
    }
  REQUIRE(std::stod(cells[2]) == 40e9);
  const double E_known = std::stod(cells[4]);
  // nu comes out too (measured by the same test) in the final check.
  const auto fit1 = nlohmann::json::parse(read(out1 / "fit.json"));
  REQUIRE(fit1["status"] == "targets_not_reached");
  CHECK(nlohmann::json::parse(read(out1 / "manifest.json"))["status"] ==
        "targets_not_reached");

  // 2. Start elsewhere (E* 25 GPa, kappa* 3.2) with those properties as
  //    targets: the search must come back to the known microparameters.
  const fs::path out2 = work_dir() / "fit";
  fs::remove_all(out2);
  const auto         m1       = nlohmann::json::parse(read(out1 / "material.json"));
  const double       nu_known = m1["nu"];
  std::ostringstream targets;
  targets.precision(17);
  targets << search
          << "  set evaluations = 60\n  subsection Targets\n    set E = " << E_known
          << ", 1, 0.002\n    set nu = " << nu_known << ", 1, 0.005\n  end\n";
  const auto r2 = run_demfem(
      "calibrate " + write("fit.prm", prm(out2, 25e9, 3.2, targets.str())).string() +
      " --fit");
  INFO(r2.out);
  // material.json of step 1 is the calibrated start material: its E is the
  // fit.csv value (same packing, same test).
  CHECK(m1["E"].get<double>() == Approx(E_known).epsilon(1e-12));
  REQUIRE(r2.exit_code == 0);
  CHECK(nlohmann::json::parse(read(out2 / "manifest.json"))["status"] == "ok");
  const auto fit = nlohmann::json::parse(read(out2 / "fit.json"));
  CHECK(fit["status"] == "ok");
  // E is proportional to E* on a fixed packing: a 0.2 % tolerance on E
  // gives E* within about 0.5 %; nu moves slowly with kappa*, so its 0.5 %
  // tolerance leaves kappa* within a few %.
  CHECK(fit["best_parameters"]["effective modulus"].get<double>() ==
        Approx(40e9).epsilon(0.01));
  CHECK(fit["best_parameters"]["stiffness ratio"].get<double>() ==
        Approx(2).epsilon(0.05));
  for (const char *f :
       {"fit.csv", "fit_convergence.svg", "fit_front.csv", "fit_front.json",
        "fit_front.svg", "material.json", "summary.json"})
    CHECK(fs::is_regular_file(out2 / f));
  // Which targets conflict (fit_front.*): E and nu were met together, in
  // the evaluation that ended the search.
  CHECK(fit["conflicting_targets"].empty());
  const auto front = nlohmann::json::parse(read(out2 / "fit_front.json"));
  REQUIRE(front["pairs"].size() == 1);
  CHECK(front["pairs"][0]["conflict"] == "no");
  CHECK(front["pairs"][0]["best_joint"].get<double>() <= 1);

  // 3. Fit/resume from: the same fit stopped after its first five
  //    evaluations (fit.csv is rewritten after each, so that is what a
  //    stopped run leaves) and resumed replays them and then measures
  //    exactly what the uninterrupted fit measured: the search and the
  //    measurements are deterministic, and the log keeps 17 digits.
  const auto split = [](const std::string &text, char sep) {
    std::vector<std::string> v;
    std::stringstream        s(text);
    for (std::string x; std::getline(s, x, sep);)
      v.push_back(x);
    if (!text.empty() && text.back() == sep && sep == ',')
      v.push_back("");
    return v;
  };
  const auto full = split(read(out2 / "fit.csv"), '\n');
  REQUIRE(full.size() > 7); // the header and more than six evaluations
  std::string stopped;
  for (std::size_t k = 0; k <= 5; ++k)
    stopped += full[k] + "\n";
  const fs::path stopped_csv = write("stopped.csv", stopped);
  const fs::path out3        = work_dir() / "resumed";
  fs::remove_all(out3);
  const auto resume = [&](const fs::path &log) {
    return targets.str() + "  set resume from = " + log.string() + "\n";
  };
  const auto r3 = run_demfem(
      "calibrate " +
      write("resumed.prm", prm(out3, 25e9, 3.2, resume(stopped_csv))).string() +
      " --fit");
  INFO(r3.out);
  REQUIRE(r3.exit_code == 0);
  CHECK(r3.out.find("resuming: 5 evaluations") != std::string::npos);
  const auto again = split(read(out3 / "fit.csv"), '\n');
  REQUIRE(again.size() == full.size());
  for (std::size_t k = 1; k < full.size(); ++k)
    {
      INFO("fit.csv row " << k);
      auto a = split(full[k], ','), b = split(again[k], ',');
      REQUIRE(a.size() == b.size());
      // The note marks a replayed row; the seconds of a measured one are
      // its own. Everything else, the objective included, is the same.
      CHECK((b.back().rfind("replayed", 0) == 0) == (k <= 5));
      if (k > 5)
        a[a.size() - 3] = b[b.size() - 3];
      a.pop_back(), b.pop_back();
      CHECK(a == b);
    }
  const auto fit3 = nlohmann::json::parse(read(out3 / "fit.json"));
  CHECK(fit3["best_parameters"] == fit["best_parameters"]);
  CHECK(fit3["replayed_evaluations"] == 5);
  CHECK(fit3["resumed_from"] == stopped_csv.string());

  // 4. A log of other targets (step 1 searched for E only), or a damaged
  //    one, is refused naming the key and the file, before anything runs.
  std::string damaged = stopped;
  damaged.insert(damaged.find('\n', damaged.find('\n') + 1), ",1");
  for (const fs::path &log : {out1 / "fit.csv", write("damaged.csv", damaged)})
    {
      const fs::path out4 = work_dir() / "refused";
      fs::remove_all(out4);
      const auto r4 = run_demfem(
          "calibrate " +
          write("refused.prm", prm(out4, 25e9, 3.2, resume(log))).string() + " --fit");
      INFO(r4.out);
      CHECK(r4.exit_code == 1);
      CHECK(r4.out.find("Fit/resume from = " + log.string()) != std::string::npos);
      CHECK(!fs::exists(out4));
    }
}

TEST_CASE("calibrate --fit refuses bad targets and empty search spaces",
          "[calibrate][fit]")
{
  struct Case
  {
    const char *name, *fit, *key;
  };
  const std::string ok_params = "  set parameters = effective modulus 10e9 100e9\n";
  const Case        cases[]   = {
               {"negative_E", "  subsection Targets\n    set E = -1e9\n  end\n", "Fit/Targets/E"},
               {"nu_half", "  subsection Targets\n    set nu = 0.5\n  end\n", "Fit/Targets/nu"},
               {"dt_above_ucs",
                "  subsection Targets\n    set ucs = 100e6\n    set direct tension = 120e6\n  "
                         "end\n",
                "Fit/Targets/direct tension"},
               {"trailing", "  subsection Targets\n    set E = 69e9x\n  end\n", "Fit/Targets/E"},
               {"no_targets", "", "Fit/Targets"},
               {"brazilian_seeds",
                "  set brazilian seeds = -1\n  subsection Targets\n    set "
                         "E = 30e9\n  end\n",
                "Fit/brazilian seeds"}};
  for (const auto &c : cases)
    {
      SECTION(c.name)
      {
        const fs::path out = work_dir() / (std::string("bad_") + c.name);
        fs::remove_all(out);
        const auto r = run_demfem(
            "calibrate " +
            write(std::string(c.name) + ".prm", prm(out, 40e9, 2, ok_params + c.fit))
                .string() +
            " --fit");
        INFO(r.out);
        CHECK(r.exit_code == 1);
        CHECK(r.out.find(c.key) != std::string::npos);
        CHECK(!fs::exists(out));
      }
    }
  SECTION("empty search space")
  {
    const fs::path out = work_dir() / "bad_space";
    const auto     r   = run_demfem(
              "calibrate " +
              write("space.prm", prm(out, 40e9, 2,
                                     "  set parameters = effective modulus 50e9 50e9\n"
                                           "  subsection Targets\n    set E = 30e9\n  end\n"))
                  .string() +
              " --fit");
    CHECK(r.exit_code == 1);
    CHECK(r.out.find("empty search space") != std::string::npos);
    CHECK(!fs::exists(out));
  }
  SECTION("no parameters, unknown parameter")
  {
    for (const char *p : {"", "  set parameters = grain colour 1 2\n"})
      {
        const fs::path out = work_dir() / "bad_param";
        const auto     r   = run_demfem(
                  "calibrate " +
                  write("param.prm",
                        prm(out, 40e9, 2,
                            std::string(p) + "  subsection Targets\n    set E = 30e9\n  end\n"))
                      .string() +
                  " --fit");
        CHECK(r.exit_code == 1);
        CHECK(r.out.find("Fit/parameters") != std::string::npos);
        CHECK(!fs::exists(out));
      }
  }
}

TEST_CASE("calibrate --fit does not take a disk that did not split as a BTS",
          "[calibrate][fit][brazilian]")
{
  // The unbreakable material of the fit above, stopped at an axial strain
  // of 1e-3: its Brazilian disk never breaks, so no packing gives a BTS
  // (docs/calibrate.md, "Failure mode of the Brazilian test"). The
  // evaluation fails naming the packing and its failure mode instead of
  // scoring the load at the strain limit, and the best material's
  // calibration ends brazilian_not_split (exit 3), not targets_not_reached.
  const fs::path out = work_dir() / "not_split";
  fs::remove_all(out);
  const auto r = run_demfem(
      "calibrate " +
      write("not_split.prm",
            prm(out, 40e9, 2,
                "  set parameters = effective modulus 10e9 100e9\n"
                "  set evaluations = 1\n  subsection Targets\n    set bts = 8.8e6\n"
                "  end\n"))
          .string() +
      " --set \"Tests/tests=brazilian\" --fit");
  INFO(r.out);
  CHECK(r.exit_code == 3);
  std::istringstream csv(read(out / "fit.csv"));
  std::string        header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  CHECK(header.find(",error,note") != std::string::npos);
  CHECK(row.find("no Brazilian disk split along its loaded diameter: seed 10000 "
                 "Brazilian no_failure") != std::string::npos);
  const auto fit = nlohmann::json::parse(read(out / "fit.json"));
  CHECK(fit["targets"]["bts"]["seed_mean"].is_null());
  CHECK(nlohmann::json::parse(read(out / "manifest.json"))["status"] ==
        "brazilian_not_split");
  CHECK(nlohmann::json::parse(read(out / "material.json"))["bts"].is_null());
}

TEST_CASE("calibrate --fit takes the bts over Fit/brazilian seeds disks",
          "[calibrate][fit][brazilian]")
{
  // Fit/seeds = 1, Fit/brazilian seeds = 3, the disk packed on its own
  // (Tests/brazilian diameter): every evaluation measures E on packing
  // 10000 only and tests three Brazilian disks, 10000-10002; packings 10001
  // and 10002 run no compression test (E has no seed scatter). The
  // unbreakable disks never split, so the error names all three, which
  // shows each was tested.
  const auto [out, r] =
      calibrate_in("bts_disks",
                   "  set parameters = effective modulus 10e9 100e9\n"
                   "  set evaluations = 1\n  set brazilian seeds = 3\n"
                   "  subsection Targets\n    set E = 30e9\n    set bts = 8.8e6\n"
                   "  end\n",
                   " --set \"Tests/tests=ucs, brazilian\" --set \"Tests/brazilian "
                   "diameter=0.014\" --fit");
  INFO(r.out);
  CHECK(r.out.find("the bts over 3 Brazilian disks per evaluation") != std::string::npos);
  bool strength_row = false;
  for (const auto &row : csv_rows(out / "fit.csv"))
    if (row.size() > 2 && row[1] != "stage" && row[1] != "elastic")
      {
        strength_row = true;
        // E from packing 10000 alone: three compression tests of three
        // packings would give a seed scatter (columns: evaluation, stage,
        // effective_modulus, E_mean, E_sd, ...).
        CHECK(row[4] == "0");
        const std::string error = row[row.size() - 2];
        for (const char *seed : {"10000", "10001", "10002"})
          CHECK(error.find(std::string("seed ") + seed + " Brazilian no_failure") !=
                std::string::npos);
        CHECK(error.find("seed 10003") == std::string::npos);
      }
  CHECK(strength_row);
  CHECK(nlohmann::json::parse(read(out / "fit.json"))["brazilian_seeds"] == 3);
}

TEST_CASE("calibrate --fit measures its packings side by side as one at a time",
          "[calibrate][fit]")
{
  // Two packings per evaluation (Fit/seeds = 2) on two threads run side by
  // side, one thread each (apps/parallel_packings.h); on one thread one
  // after the other. Every logged measurement and the best material's file
  // must be the same bytes; only the seconds column may differ.
  const std::string fit = "  set parameters = effective modulus 10e9 100e9\n"
                          "  set evaluations = 2\n  subsection Targets\n"
                          "    set E = 30e9\n  end\n";
  auto              run = [&](const std::string &name, const int threads) {
    const fs::path out = work_dir() / name;
    fs::remove_all(out);
    const auto r = demfem::testing::run_with_threads(
                     "calibrate " + write(name + ".prm", prm(out, 40e9, 2, fit)).string() +
                         " --set Fit/seeds=2 --fit",
                     threads);
    INFO(r.out);
    CHECK((r.exit_code == 0 || r.exit_code == 3));
    CHECK((r.out.find("2 packings per evaluation, 2 at a time") != std::string::npos) ==
                       (threads == 2));
    return out;
  };
  const fs::path side = run("fit_side", 2), one = run("fit_one", 1);
  // fit.csv without its seconds column (the third from the end).
  auto rows = [](const fs::path &csv) {
    std::vector<std::string> out;
    for (auto c : csv_rows(csv))
      {
        REQUIRE(c.size() >= 4);
        c.erase(c.end() - 3);
        std::string joined;
        for (const auto &x : c)
          joined += x + ",";
        out.push_back(joined);
      }
    return out;
  };
  const auto a = rows(side / "fit.csv"), b = rows(one / "fit.csv");
  REQUIRE(a.size() >= 3); // the header and at least two evaluations
  CHECK(a == b);
  CHECK(read(side / "material.json") == read(one / "material.json"));
}

TEST_CASE(
    "calibrate --fit: the elastic stage measures E and nu in the window of the full "
    "test at the target UCS",
    "[calibrate][fit]")
{
  // With the modulus window a fraction of the peak (Tests/fit window
  // low/high, here the defaults 0.1-0.5), the elastic stage's short test
  // (Fit/elastic strain 3e-4) would measure at 10-50 % of its own end
  // load; with a UCS target it measures in 0.1-0.5 x that target and runs
  // until its platen strain is 1.5 x 0.5 x UCS / E_target (elastic_test_
  // settings in apps/calibrate_fit.cc). On the unbreakable material loaded
  // to 1e-3 (its "peak" is its load there), a UCS target equal to that load
  // makes the elastic stage's window the full test's: the same rows of the
  // same deterministic loading (the elastic test runs on to 1.5 x 0.5 x
  // UCS / 10 GPa > 1e-3, its later rows above the window), so the same E
  // and nu to round-off; the full test stopped at 3e-4 (what the elastic
  // stage measured before) reads others.
  auto calibrate = [&](const std::string &name, const std::string &fit,
                       const std::string &args) {
    const auto [out, r] = calibrate_in(name, fit, args);
    INFO(r.out);
    REQUIRE((r.exit_code == 0 || (r.exit_code == 3 && args == " --fit")));
    return out;
  };
  const auto m1 =
      nlohmann::json::parse(read(calibrate("window_full", "", "") / "material.json"));
  const double       ucs = m1["ucs"], E = m1["E"], nu = m1["nu"];
  std::ostringstream fit;
  fit.precision(17);
  fit << "  set elastic strain = 3e-4\n"
         "  set parameters = effective modulus 10e9 100e9\n"
         "  set evaluations = 1\n  subsection Targets\n    set E = 10e9\n"
         "    set nu = 0.1\n    set ucs = "
      << ucs << "\n  end\n";
  std::istringstream csv(read(calibrate("window_fit", fit.str(), " --fit") / "fit.csv"));
  auto               cells = [](const std::string &line) {
    std::vector<std::string> c;
    std::stringstream        s(line);
    for (std::string x; std::getline(s, x, ',');)
      c.push_back(x);
    return c;
  };
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  const auto names = cells(header), values = cells(row);
  auto       at = [&](const std::string &name) {
    const auto i = std::find(names.begin(), names.end(), name) - names.begin();
    REQUIRE(std::size_t(i) < values.size());
    return std::stod(values[i]);
  };
  REQUIRE(values[1] == "elastic");
  CHECK(at("E_mean") == Approx(E).epsilon(1e-12));
  CHECK(at("nu_mean") == Approx(nu).epsilon(1e-12));
  const auto m3 = nlohmann::json::parse(
      read(calibrate("window_short", "", " --set \"Tests/strain limit=3e-4\"") /
           "material.json"));
  CHECK(std::abs(m3["E"].get<double>() / E - 1) > 1e-6);
}

TEST_CASE("calibrate --fit takes the strength stage's measurement as its check",
          "[calibrate][fit]")
{
  // On the unbreakable material of the tests above, with the targets the
  // start material's own E and UCS (its load at the strain limit): the
  // elastic stage reads the full test's E (the window test above) and
  // stops at its first evaluation, the strength stage (tensile strength
  // mean, which cannot move this material) at its first. Its measurement
  // ran the full UCS test on every target at the fitted parameters, so
  // the check (stage `check`) is that measurement, logged with a note that
  // says so and no seconds, not a third evaluation; a fit with only
  // elastic targets measures its check (its stage's short test is not the
  // full one). A resumed fit takes the logged check row as its own.
  auto calibrate = [&](const std::string &name, const std::string &fit,
                       const std::string &args) {
    const auto [out, r] = calibrate_in(name, fit, args);
    INFO(r.out);
    REQUIRE(r.exit_code == 0);
    return std::make_pair(out, r.out);
  };
  const auto m = nlohmann::json::parse(
      read(calibrate("check_known", "", "").first / "material.json"));
  std::ostringstream targets;
  targets.precision(17);
  targets << "  subsection Targets\n    set E = " << m["E"].get<double>()
          << "\n    set ucs = " << m["ucs"].get<double>() << "\n  end\n";
  const std::string search = "  set parameters = effective modulus 10e9 100e9; "
                             "tensile strength mean 1e11 1e13\n  set evaluations = 4\n";
  const auto [out, log]    = calibrate("check_reused", search + targets.str(), " --fit");
  const auto r             = csv_rows(out / "fit.csv");
  REQUIRE(r.size() == 4); // the header, elastic, strength, check
  const auto &h   = r[0];
  auto        col = [&](const std::string &name) {
    const auto i = std::size_t(std::find(h.begin(), h.end(), name) - h.begin());
    REQUIRE(i < h.size());
    return i;
  };
  CHECK(r[1][1] == "elastic");
  CHECK(r[2][1] == "strength");
  REQUIRE(r[3][1] == "check");
  CHECK(r[3][col("note")] ==
        "the measurement of evaluation 2 (strength): the same parameters on the same "
        "packings by the same tests");
  CHECK(std::stod(r[3][col("seconds")]) == 0);
  for (const char *c : {"effective_modulus", "tensile_strength_mean", "E_mean",
                        "ucs_mean", "objective", "all_within_tolerance"})
    CHECK(r[3][col(c)] == r[2][col(c)]);
  CHECK(log.find("(evaluation 2, not measured again)") != std::string::npos);
  const auto fit = nlohmann::json::parse(read(out / "fit.json"));
  CHECK(fit["status"] == "ok");
  // The material file of the best parameters is measured (one packing, the
  // same seed and tests): its E and UCS are the check's.
  const auto best = nlohmann::json::parse(read(out / "material.json"));
  CHECK(best["E"].get<double>() == Approx(std::stod(r[3][col("E_mean")])).epsilon(1e-12));
  CHECK(best["ucs"].get<double>() ==
        Approx(std::stod(r[3][col("ucs_mean")])).epsilon(1e-12));

  // Resumed from that log: two rows replayed, the check row taken as this
  // fit's own (the same row again), nothing measured.
  const fs::path saved    = write("check_reused.csv", read(out / "fit.csv"));
  const auto [out2, log2] = calibrate(
      "check_resumed",
      search + targets.str() + "  set resume from = " + saved.string() + "\n", " --fit");
  const auto r2 = csv_rows(out2 / "fit.csv");
  REQUIRE(r2.size() == r.size());
  CHECK(r2[3] == r[3]);

  // Elastic targets only: the check is measured by the full test.
  std::ostringstream elastic;
  elastic.precision(17);
  elastic << "  set parameters = effective modulus 10e9 100e9\n  set evaluations = 4\n"
          << "  subsection Targets\n    set E = " << m["E"].get<double>() << "\n  end\n";
  const auto [out3, log3] = calibrate("check_measured", elastic.str(), " --fit");
  const auto r3           = csv_rows(out3 / "fit.csv");
  REQUIRE(r3.size() == 3); // the header, elastic, check
  REQUIRE(r3[2][1] == "check");
  CHECK(r3[2].back().empty()); // the note, the last column
  CHECK(log3.find("not measured again") == std::string::npos);
}

TEST_CASE("calibrate --fit writes the best material on Problem/seeds packings",
          "[calibrate][fit]")
{
  // Problem/seeds = Fit/seeds = 2: the best material's material.json is the
  // seed mean of the two packings the fit measured, so its E is the
  // check's (the same packings and test; the means to round-off), and it
  // lists both seeds.
  const auto [out, r] =
      calibrate_in("final_seeds",
                   "  set parameters = effective modulus 10e9 100e9\n"
                   "  set evaluations = 1\n  subsection Targets\n    set E = 1e9\n"
                   "  end\n",
                   " --set Fit/seeds=2 --set Problem/seeds=2 --fit");
  INFO(r.out);
  REQUIRE(r.exit_code == 3); // the dummy target was not reached
  std::istringstream csv(read(out / "fit.csv"));
  std::string        header, row, check;
  std::getline(csv, header);
  std::getline(csv, row);
  std::getline(csv, check);
  std::vector<std::string> cells;
  for (std::stringstream c(check); c.good();)
    {
      std::string x;
      std::getline(c, x, ',');
      cells.push_back(x);
    }
  REQUIRE(cells.size() > 4);
  REQUIRE(cells[1] == "check");
  const auto m = nlohmann::json::parse(read(out / "material.json"));
  CHECK(m["seeds"] == nlohmann::json::array({10000, 10001}));
  // Two values averaged in another order: a few ulp.
  CHECK(m["E"].get<double>() == Approx(std::stod(cells[3])).epsilon(1e-12));
  CHECK(fs::is_regular_file(out / "seed_10001" / "material.json"));
}
