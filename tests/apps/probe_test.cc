// `demfem tunnel --probe` (apps/tunnel_probe.h; docs/tunnel.md, "The probe"):
// lab specimens built by the region's genesis at the region's grain size
// reproduce the material file.
#include <catch2/catch.hpp>

#include "run_command.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

using demfem::testing::run_demfem;
using json = nlohmann::json;

namespace
{
  const std::string examples = std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/";

  json read_json(const std::string &f)
  {
    std::ifstream in(f);
    return json::parse(in);
  }

  // A small calibrated material (the Lac du Bonnet example in a 12.5 x 25 mm
  // vessel, about 250 grains; UCS and Brazilian at 0.25 /s, about 15 s): its
  // material.json in a directory of the test's own (ctest runs the test
  // cases in parallel processes). Packing 10001 by default: its disk and
  // packing 10002's (the probe's second seed) split; packing 10000's does
  // not (below). E*, the flat joints' strengths and friction angle are pinned
  // to the values these facts were measured with, so that re-tuning the
  // example does not change what is tested.
  std::string small_material(const std::string &tag, const std::string &extra = "",
                             int expected_exit = 0)
  {
    {
      const std::string dir =
          (std::filesystem::temp_directory_path() / ("demfem_probe_lab_" + tag)).string();
      std::filesystem::remove_all(dir);
      const auto r = run_demfem(
          "calibrate " + examples +
          "lac_du_bonnet_2d.prm --set Tests/tests=ucs,brazilian --set \"Tests/strain "
          "rate=0.25\" --set \"Tests/loading "
          "rate check=false\" --set Problem/vtk=false --set \"Material/number of "
          "grains=250\" --set Vessel/height=0.025 --set Vessel/width=0.0125 --set "
          "\"Problem/output directory=" +
          dir +
          "\" --set Material/seed=10001"
          " --set \"Material/effective modulus=106e9\""
          " --set \"Material/Flat joint/tensile strength mean=22.8e6\""
          " --set \"Material/Flat joint/tensile strength sd=9.6e6\""
          " --set \"Material/Flat joint/tensile strength min=10e6\""
          " --set \"Material/Flat joint/friction angle=20\" " +
          extra);
      INFO(r.out);
      REQUIRE(r.exit_code == expected_exit);
      return dir + "/material.json";
    }
  }

  // The region's mean grain diameter that makes the grain-size factor
  // exactly 32 (apps/tunnel_prm.cc: k = d / mean diameter of the file).
  std::string diameter_times_32(const json &m)
  {
    const double mult = m["microparameters"]["diameter_multiplier"].get<double>();
    const auto  &p    = m["microparameters"]["size_distribution"]["piece_0"];
    const double mean =
        0.5 * (mult * p["D_lo_m"].get<double>() + mult * p["D_hi_m"].get<double>());
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", 32 * mean);
    return buf;
  }

  // The probe's output directory for a test case of its own.
  std::string probe_dir(const std::string &tag)
  {
    return (std::filesystem::temp_directory_path() / ("demfem_probe_" + tag)).string();
  }

  // An edited material file written next to `dir`; returns its path.
  std::string write_material(const json &m, const std::string &dir)
  {
    std::filesystem::create_directories(dir);
    const std::string file = dir + ".material.json";
    std::ofstream     out(file);
    out << m.dump(2);
    return file;
  }

  demfem::testing::CommandResult probe(const std::string &material,
                                       const std::string &diameter,
                                       const std::string &dir,
                                       const std::string &extra = "", int seeds = 1,
                                       int threads = 0)
  {
    std::filesystem::remove_all(dir);
    const std::string args =
        "tunnel " + examples +
        "tunnel_2d.prm --set \"DEM region/material file=" + material +
        "\" --set \"DEM region/grain diameter=" + diameter +
        "\" --set \"Problem/output directory=" + dir + "\" --probe --probe-seeds " +
        std::to_string(seeds) + " " + extra;
    return threads > 0 ? demfem::testing::run_with_threads(args, threads)
                       : run_demfem(args);
  }
} // namespace

TEST_CASE("probe: at 32 times the grain size the lab tests give the material file's "
          "numbers exactly",
          "[probe][app]")
{
  // Twice: the Brazilian disk carved from the 12.5 mm vessel, and a disk
  // of its own 30 mm across (Tests/brazilian diameter, recorded in the
  // file's lab_tests and scaled by the factor like every length).
  const bool        own = GENERATE(false, true);
  const std::string file =
      own ? small_material("exact_own_disk", "--set \"Tests/brazilian diameter=0.03\"")
          : small_material("exact");
  const json m = read_json(file);
  CHECK(m["lab_tests"]["brazilian_diameter_m"].get<double>() == (own ? 0.03 : 0));
  const std::string dir = (std::filesystem::temp_directory_path() /
                           (own ? "demfem_probe_own" : "demfem_probe"))
                              .string();
  const auto r = probe(file, diameter_times_32(m), dir);
  INFO(r.out);
  CHECK((r.out.find("Brazilian specimen of its own, 0.96 m across") !=
         std::string::npos) == own);
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("probe: pass") != std::string::npos);
  const json p = read_json(dir + "/probe.json");
  CHECK(p["grain_size_factor"].get<double>() == 32);
  CHECK(p["pass"].get<bool>());
  // Scaling every length by a power of two is exact in floating point, and
  // the probe divides the strain rate by the same factor (the time step
  // grows with the grain size): the packing and the tests are the same
  // computation, bit for bit, unless something in the genesis or the tests
  // is not scale-free (an absolute length, time or velocity). Same seed
  // (the material's): E, nu, UCS and BTS equal to round-off.
  for (const auto &row : p["rows"])
    {
      const std::string name = row["property"];
      const double      want = row["material_file"], got = row["probe_mean"];
      INFO(name << ": probe " << got << ", material file " << want);
      CHECK(std::abs(got - want) <= 1e-12 * std::abs(want));
    }
  // The packing is reported beside them (not judged): the same packing,
  // so the same porosities to round-off.
  for (const char *name : {"porosity", "measurement_porosity"})
    {
      const double want = p[name]["material_file"], got = p[name]["probe_mean"];
      INFO(name << ": probe " << got << ", material file " << want);
      CHECK(want > 0.1);
      CHECK(std::abs(got - want) <= 1e-12 * want);
    }
  CHECK(r.out.find("reported, not judged") != std::string::npos);
}

TEST_CASE("probe: packings side by side on two threads report what one thread reports",
          "[probe][app]")
{
  // Three packings: on two threads two run side by side
  // (apps/parallel_packings.h), each on its own copies of the material and
  // the test settings, and their lines are written in seed order. The
  // contact loop does not depend on the thread count, so the report (the
  // packings' lines and probe.json) is the one thread's, byte for byte.
  const std::string file = small_material("threads");
  const json        m    = read_json(file);
  std::string       report[2], lines[2];
  int               exit_code[2] = {-1, -1};
  for (const int threads : {1, 2})
    {
      const std::string dir = probe_dir("threads_" + std::to_string(threads));
      const auto        r   = probe(file, diameter_times_32(m), dir, "", 3, threads);
      INFO(r.out);
      // A verdict (0 pass, 3 fail), not an error: both runs end alike.
      REQUIRE((r.exit_code == 0 || r.exit_code == 3));
      exit_code[threads - 1] = r.exit_code;
      std::ifstream in(dir + "/probe.json");
      report[threads - 1] = std::string(std::istreambuf_iterator<char>(in), {});
      std::istringstream out(r.out);
      for (std::string line; std::getline(out, line);)
        if (line.rfind("probe: seed ", 0) == 0 || line.rfind("genesis:", 0) == 0)
          lines[threads - 1] += line + "\n";
    }
  CHECK(exit_code[0] == exit_code[1]);
  CHECK(report[0] == report[1]);
  CHECK(lines[0] == lines[1]);
  // In seed order, each packing once.
  const auto a = lines[1].find("probe: seed 10001:"),
             b = lines[1].find("probe: seed 10002:"),
             c = lines[1].find("probe: seed 10003:");
  CHECK(a < b);
  CHECK(b < c);
  CHECK(c != std::string::npos);
}

TEST_CASE("probe: a material file whose E the region does not reproduce fails",
          "[probe][app]")
{
  // The same material with E raised by 10 % in the file: the region's
  // grains are unchanged, so the probe's E is 9 % below the file's; the
  // continuum takes the (raised) file value, which still passes.
  json m                 = read_json(small_material("bad"));
  m["E"]                 = 1.1 * m["E"].get<double>();
  const std::string dir  = probe_dir("bad");
  const std::string file = write_material(m, dir);
  const auto        r    = probe(file, diameter_times_32(m), dir);
  INFO(r.out);
  CHECK(r.exit_code == 3);
  CHECK(r.out.find("probe: FAIL") != std::string::npos);
  const json p = read_json(dir + "/probe.json");
  CHECK_FALSE(p["pass"].get<bool>());
  CHECK(p["rows"][0]["property"] == "E");
  CHECK(p["rows"][0]["verdict"] == "FAIL");
  CHECK(p["rows"][0]["difference"].get<double>() == Approx(1 / 1.1 - 1).epsilon(1e-9));
  CHECK(p["rows"][1]["verdict"] == "pass"); // nu unchanged
}

TEST_CASE("probe: the strengths are judged by the standard error of the difference of "
          "the seed means, with the file's scatter",
          "[probe][app]")
{
  // A file that says it is the mean of three packings (seed_scatter,
  // seed_values) with its UCS tripled: the probe's two packings read the
  // real UCS, so the UCS row fails, with the standard error
  // sqrt(s_p^2 / 2 + s_f^2 / 3) (common/statistics.h, compare_means). The
  // BTS was measured on two of the three packings (a null: a disk that did
  // not split), so its file scatter counts two.
  json         m   = read_json(small_material("scatter"));
  const double ucs = 3 * m["ucs"].get<double>(), bts = m["bts"].get<double>();
  m["ucs"]                 = ucs;
  m["seeds"]               = json::array({10000, 10001, 10002});
  m["seed_values"]["ucs"]  = json::array({0.9 * ucs, ucs, 1.1 * ucs});
  m["seed_scatter"]["ucs"] = 0.1 * ucs;
  m["seed_values"]["bts"]  = json::array({0.8 * bts, nullptr, 1.2 * bts});
  m["seed_scatter"]["bts"] = 0.4 * bts / std::sqrt(2.0);
  const std::string dir    = probe_dir("scatter");
  const std::string file   = write_material(m, dir);
  const auto        r      = probe(file, diameter_times_32(m), dir, "", 2);
  INFO(r.out);
  CHECK(r.exit_code == 3);
  const json p = read_json(dir + "/probe.json");
  REQUIRE(p["rows"][2]["property"] == "UCS");
  REQUIRE(p["rows"][3]["property"] == "BTS");
  auto sd2 = [](const json &values) { // sample variance of two values
    const double a = values[0], b = values[1];
    return 0.5 * (a - b) * (a - b);
  };
  const json &u = p["rows"][2];
  CHECK(u["verdict"] == "FAIL");
  CHECK(u["material_file_sd"].get<double>() == Approx(0.1 * ucs).epsilon(1e-12));
  CHECK(u["standard_error"].get<double>() ==
        Approx(std::sqrt(sd2(u["probe_values"]) / 2 + 0.01 * ucs * ucs / 3))
            .epsilon(1e-12));
  CHECK(u["rule"].get<std::string>().find("3 file packings") != std::string::npos);
  // Welch's t test: nu from both scatters (2 probe, 3 file packings).
  {
    const double va = sd2(u["probe_values"]) / 2, vb = 0.01 * ucs * ucs / 3;
    CHECK(u["degrees_of_freedom"].get<double>() ==
          Approx((va + vb) * (va + vb) / (va * va / 1 + vb * vb / 2)).epsilon(1e-12));
    CHECK(u["critical_t"].get<double>() > 1.96);
  }
  const json  &b  = p["rows"][3];
  const double sb = 0.4 * bts / std::sqrt(2.0);
  CHECK(b["standard_error"].get<double>() ==
        Approx(std::sqrt(sd2(b["probe_values"]) / 2 + sb * sb / 2)).epsilon(1e-12));
  CHECK(b["rule"].get<std::string>().find("2 file packings") != std::string::npos);
}

TEST_CASE("probe: without a material file the keys' material is held to the continuum's "
          "E, nu",
          "[probe][app]")
{
  // apps/examples/study_breakable_2d.prm has no material file: its region
  // is the DEM region keys' material (E* 20 GPa, weak flat joints) at a/d =
  // 4 (d = 0.1 m), its continuum given E, nu by hand. The probe builds the
  // keys' material in a lab box of 30 x 60 mean diameters and runs the UCS
  // test: the example's pair must be the material's within 5 % (one seed:
  // E has a seed scatter of about 2.5 %, nu about 5 %, over three packings,
  // docs/tunnel.md "The probe"). The example's former pair, 16.3 GPa and
  // 0.11, was 7 % stiffer than the material (measured), which put the
  // region 2-3 % below the in-situ stress and read less damage.
  const std::string dir = probe_dir("keys");
  std::filesystem::remove_all(dir);
  auto probe_example = [&](const std::string &extra) {
    return run_demfem("tunnel " + examples +
                      "study_breakable_2d.prm --probe --probe-seeds 1 --set "
                      "\"Problem/output directory=" +
                      dir + "\" " + extra);
  };
  const auto r = probe_example("");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const json p = read_json(dir + "/probe.json");
  CHECK(p["compared_with"] == "continuum");
  CHECK(p["material_file"].is_null());
  CHECK(p["pass"] == true);
  REQUIRE(p["rows"].size() == 3); // E, nu, UCS; no Brazilian without strengths
  const json &E = p["rows"][0], &nu = p["rows"][1], &ucs = p["rows"][2];
  CHECK(E["property"] == "E");
  CHECK(E["verdict"] == "pass");
  CHECK(nu["verdict"] == "pass");
  const double e = E["probe_mean"].get<double>();
  CHECK(std::abs(e / p["continuum_E"].get<double>() - 1) <= 0.05);
  CHECK(std::abs(16.3e9 / e - 1) > 0.05); // the former pair fails
  // The strength is reported, with nothing to judge it against.
  CHECK(ucs["verdict"] == "-");
  CHECK(ucs["continuum"].is_null());
  CHECK(ucs["probe_mean"].get<double>() > 0);

  // Unbreakable bonds: no peak, the test ends at 0.1 % strain and the
  // moduli come from its linear branch: the same packing's E and nu as the
  // breakable specimen's 5-20 % window, where its bonds are intact
  // (measured 0.24 % and 0.4 % apart; 1 % and 2 % allowed), and no UCS.
  const auto u = probe_example("--set \"DEM region/breakable=false\"");
  INFO(u.out);
  REQUIRE(u.exit_code == 0);
  const json q = read_json(dir + "/probe.json");
  REQUIRE(q["rows"].size() == 2);
  CHECK(q["rows"][0]["probe_mean"].get<double>() == Approx(e).epsilon(0.01));
  CHECK(q["rows"][1]["probe_mean"].get<double>() ==
        Approx(nu["probe_mean"].get<double>()).epsilon(0.02));
}

TEST_CASE("probe: DEM region/seed picks the packing, by default the material file's",
          "[probe][app]")
{
  // DEM region/seed = material (the default) packs the material file's
  // realization; an integer packs another one (a seed sweep of tunnel runs);
  // anything else is refused naming the key. This packing's 250-grain disk
  // with the example's 20 deg flats splits (7 of its 9 failure
  // cracks in the split zone), so the probe's one seed passes.
  const std::string file = small_material("seed", "--set Material/seed=4242");
  const json        m    = read_json(file);
  REQUIRE(m["microparameters"]["seed"].get<long long>() == 4242);
  const std::string dir =
      (std::filesystem::temp_directory_path() / "demfem_probe_seed").string();
  const auto r = probe(file, diameter_times_32(m), dir);
  INFO(r.out);
  CHECK(r.exit_code == 0);
  CHECK(read_json(dir + "/probe.json")["first_seed"].get<long long>() == 4242);
  CHECK(r.out.find("probe: seed 4242:") != std::string::npos);

  const auto other =
      probe(file, diameter_times_32(m), dir, "--set \"DEM region/seed=77\"");
  INFO(other.out);
  CHECK(read_json(dir + "/probe.json")["first_seed"].get<long long>() == 77);
  CHECK(other.out.find("probe: seed 77:") != std::string::npos);

  const auto bad =
      probe(file, diameter_times_32(m), dir, "--set \"DEM region/seed=7.5\"");
  INFO(bad.out);
  CHECK(bad.exit_code == 1);
  CHECK(bad.out.find("DEM region/seed") != std::string::npos);
}

TEST_CASE("probe: a Brazilian disk that did not split gives no BTS", "[probe][app]")
{
  // Packing 10000's 250-grain disk with the example's 20 deg flats does not
  // split (demfem calibrate: bts null, 10 of its 22 failure cracks in the
  // split zone, exit 3). At 32 times the grain size
  // the probe's disk of the same packing is the same disk: its peak is
  // reported, but it is no tensile strength, so the BTS row has no value
  // (as calibrate's seed mean leaves it out) and the split row fails.
  const std::string file = small_material("not_split", "--set Material/seed=10000", 3);
  const json        m    = read_json(file);
  REQUIRE(m["bts"].is_null());
  REQUIRE(m["bts_failure_mode"] == "not_split");
  const std::string dir = probe_dir("not_split");
  const auto        r   = probe(file, diameter_times_32(m), dir);
  INFO(r.out);
  CHECK(r.exit_code == 3);
  const json p = read_json(dir + "/probe.json");
  REQUIRE(p["rows"][3]["property"] == "BTS");
  CHECK(p["rows"][3]["probe_values"].empty());
  CHECK(p["rows"][3]["verdict"] == "-");
  CHECK(p["brazilian_split"] == 0);
  REQUIRE(p["brazilian_failure_modes"].size() == 1);
  CHECK(p["brazilian_failure_modes"][0] == "not_split");
  // The disk's peak, kept beside: calibrate's own (summary.json) to round-off.
  const json s =
      read_json((std::filesystem::path(file).parent_path() / "summary.json").string());
  CHECK(p["brazilian_peaks_Pa"][0].get<double>() ==
        Approx(s["tests"]["brazilian"]["peak_Pa"].get<double>()).epsilon(1e-9));
  CHECK(r.out.find("Brazilian disks split: 0 of 1  FAIL") != std::string::npos);
}
