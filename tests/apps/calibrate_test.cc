// `demfem calibrate`: a tiny flat-jointed material runs end to end and writes
// material.json with every contract key (docs/architecture.md, "From the lab to
// the tunnel"); bad parameter files fail with a message naming the key, and
// write nothing.
#include "run_command.h"

#include <catch2/catch.hpp>

#include "dem/specimen/envelope.h"
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using demfem::testing::json_numbers;
using demfem::testing::run_demfem;

namespace
{
  fs::path work_dir()
  {
    static const fs::path d =
        fs::temp_directory_path() / ("demfem_calibrate_test_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }

  // About 150 grains, weak bonds and a fast rate so that all three tests
  // reach their peak within a few thousand steps.
  std::string tiny_prm(const fs::path &out, const std::string &material_extra = "")
  {
    std::ostringstream s;
    s << "subsection Problem\n  set dimension = 2\n  set output directory = "
      << out.string() << "\n  set vtk = true\nend\n"
      << "subsection Material\n  set type = flatjointed\n"
         "  set size distribution = uniform 1.0e-3 1.6e-3 1\n"
         "  set number of grains = 150\n"
         "  set linear effective modulus = 40e9\n  set effective modulus = 40e9\n"
         "  set stiffness ratio = 2\n  set friction = 0.6\n"
      << material_extra
      << "  subsection Flat joint\n    set tensile strength mean = 4e6\n"
         "    set cohesion mean = 40e6\n    set friction angle = 30\n  end\nend\n"
         "subsection Vessel\n  set height = 0.03\n  set width = 0.015\nend\n"
         "subsection Packing\n  set material pressure = 1e5\nend\n"
         "subsection Tests\n  set tests = ucs, brazilian, direct tension\n"
         "  set strain rate = 2\n  set strain limit = 0.01\n  set history interval = 20\n"
         "end\n";
    return s.str();
  }

  fs::path write(const std::string &name, const std::string &text)
  {
    const fs::path p = work_dir() / name;
    std::ofstream(p) << text;
    return p;
  }

  // The tiny material of `tiny_prm` calibrated into work_dir()/<name>_out
  // with extra command-line arguments (--set ...).
  struct TinyRun
  {
    fs::path                       out;
    demfem::testing::CommandResult r;
  };
  TinyRun run_tiny(const std::string &name, const std::string &args)
  {
    const fs::path out = work_dir() / (name + "_out");
    fs::remove_all(out);
    const fs::path prm = write(name + ".prm", tiny_prm(out));
    return {out, run_demfem("calibrate " + prm.string() + " " + args)};
  }

  // The tiny material with narrow tensile strengths (20 +- 2 MPa) and high
  // cohesion, whose Brazilian disks split, at 0.5 /s without VTK, plus
  // `args`, calibrated into work_dir()/<name>_out.
  TinyRun run_splitting(const std::string &name, const std::string &args)
  {
    return run_tiny(name,
                    "--set \"Problem/vtk=false\""
                    " --set \"Material/Flat joint/tensile strength mean=20e6\""
                    " --set \"Material/Flat joint/tensile strength sd=2e6\""
                    " --set \"Material/Flat joint/cohesion mean=200e6\""
                    " --set \"Tests/strain rate=0.5\" --set \"Tests/strain limit=0.02\"" +
                        args);
  }

  std::string read(const fs::path &p)
  {
    std::ifstream     f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }

  // One triaxial test of the tiny material at P_c = 6 MPa without VTK; the
  // test's summary.json entry of a TinyRun made with it.
  const std::string tiny_triaxial = " --set \"Problem/vtk=false\" --set "
                                    "\"Tests/tests=triaxial\" --set \"Tests/confining "
                                    "pressure=6e6\"";
  nlohmann::json    triaxial_summary(const TinyRun &t)
  {
    return nlohmann::json::parse(read(t.out / "summary.json"))["tests"]["triaxial"];
  }

  // `demfem calibrate` of the tiny material with `args` is refused where
  // the value enters: exit 1, the message names `key` (and `also`), and
  // nothing is written.
  void check_refused(const std::string &name, const std::string &args,
                     const std::string &key, const std::string &also = "")
  {
    const fs::path out = work_dir() / ("bad_" + name);
    fs::remove_all(out);
    const auto r = run_demfem(
        "calibrate " + write("bad_" + name + ".prm", tiny_prm(out)).string() + args);
    INFO(r.out);
    CHECK(r.exit_code == 1);
    CHECK(r.out.find(key) != std::string::npos);
    if (!also.empty())
      CHECK(r.out.find(also) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
} // namespace

TEST_CASE("calibrate: tiny 2D material end to end", "[calibrate]")
{
  const fs::path out = work_dir() / "tiny_out";
  fs::remove_all(out);
  const fs::path prm = write("tiny.prm", tiny_prm(out));
  const auto     r   = run_demfem("calibrate " + prm.string());
  INFO(r.out);
  // The Brazilian disk of this specimen has about 50 grains, 10 across: its
  // cracks spread over the disk instead of splitting it (measured: 4 of the
  // 12 failure cracks in the split zone), so the run has no BTS and says so
  // (exit 3, bts null). A disk that splits: "a Brazilian disk that splits
  // gives the BTS" below.
  REQUIRE(r.exit_code == 3);
  const std::string text = read(out / "material.json");
  const auto        v    = json_numbers(text);
  const auto        mat  = nlohmann::json::parse(text);
  CHECK(mat["bts"].is_null());
  CHECK(mat["bts_failure_mode"] == "not_split");
  CHECK(mat["bts_split_fraction"].get<double>() < 0.5);
  CHECK(nlohmann::json::parse(read(out / "summary.json"))["status"] ==
        "brazilian_not_split");
  for (const char *k :
       {"E", "nu", "E_plane_stress", "nu_plane_stress", "ucs", "direct_tension",
        "crack_initiation", "crack_initiation_crack_count", "crack_initiation_volumetric",
        "crack_initiation_lateral", "porosity", "measurement_porosity", "n_grains",
        "dim"})
    {
      INFO("key " << k);
      REQUIRE(v.count(k) == 1);
      CHECK(std::isfinite(v.at(k)));
    }
  CHECK(v.at("dim") == 2);
  // The continuum pair is the plane-strain map of the fit (docs/architecture.md,
  // "Plane-stress and plane-strain constants").
  const double nps = v.at("nu_plane_stress");
  CHECK(v.at("nu") == Approx(nps / (1 + nps)).epsilon(1e-12));
  CHECK(v.at("E") ==
        Approx(v.at("E_plane_stress") * (1 - v.at("nu") * v.at("nu"))).epsilon(1e-12));
  // Strengths are positive, crack initiation below the peak.
  CHECK(v.at("ucs") > v.at("direct_tension"));
  CHECK(v.at("direct_tension") > 0);
  CHECK(v.at("crack_initiation") > 0);
  CHECK(v.at("crack_initiation") < v.at("ucs"));
  // Both crack-initiation readings are reported; the default is the crack
  // volumetric strain (docs/calibrate.md), which lone early cracks do not
  // move, so it comes no earlier than the crack count's.
  CHECK(text.find("\"crack_initiation_method\": \"volumetric strain\"") !=
        std::string::npos);
  CHECK(v.at("crack_initiation") == v.at("crack_initiation_volumetric"));
  CHECK(v.at("crack_initiation_volumetric") >= v.at("crack_initiation_crack_count"));
  CHECK(v.at("porosity") > 0.05);
  CHECK(v.at("porosity") < 0.4);
  // Measurement regions (fistPkg §5.1) leave out the loose wall layer.
  CHECK(v.at("measurement_porosity") > 0.05);
  CHECK(v.at("measurement_porosity") < v.at("porosity"));
  for (const char *f :
       {"summary.json", "history_ucs.csv", "history_brazilian.csv",
        "history_direct_tension.csv", "ucs_stress_strain.svg", "ucs_strains.svg",
        "vtk/ucs_particles.pvd", "vtk/ucs_peak_cracks.vtp", "vtk/specimen_particles.vtp"})
    {
      INFO("file " << f);
      CHECK(fs::is_regular_file(out / f));
    }
  // Same seed -> same material.
  const fs::path out2 = work_dir() / "tiny_out2";
  fs::remove_all(out2);
  const auto r2 = run_demfem("calibrate " + prm.string() +
                             " --set \"Problem/output directory=" + out2.string() +
                             "\" --set \"Tests/tests=ucs\""
                             " --set \"Tests/crack initiation method=lateral strain\"");
  REQUIRE(r2.exit_code == 0);
  const std::string text2 = read(out2 / "material.json");
  const auto        v2    = json_numbers(text2);
  CHECK(v2.at("n_grains") == v.at("n_grains"));
  CHECK(v2.at("porosity") == v.at("porosity"));
  // The lateral strain response picked as the crack initiation.
  CHECK(text2.find("\"crack_initiation_method\": \"lateral strain\"") !=
        std::string::npos);
  CHECK(v2.at("crack_initiation") == v2.at("crack_initiation_lateral"));
}

TEST_CASE("calibrate: bad parameter files write nothing", "[calibrate]")
{
  struct Case
  {
    const char *name, *extra, *expect1, *expect2;
  };
  const Case cases[] = {
      {"fractions",
       "  set size distribution = uniform 1e-3 2e-3 0.6; uniform 2e-3 3e-3 0.3\n",
       "Material/size distribution", "sum to 1"},
      {"negative", "  set size distribution = uniform -1e-3 2e-3 1\n",
       "Material/size distribution (D_lo)", "allowed range"},
      {"unknown", "  set colour = red\n", "colour", "bad"},
      {"fj_fractions",
       "  subsection Flat joint\n    set bonded fraction = 0.8\n"
       "    set gapped fraction = 0.5\n  end\n",
       "Material/Flat joint/gapped fraction", "allowed range"},
  };
  for (const auto &c : cases)
    {
      INFO("case " << c.name);
      const fs::path out = work_dir() / (std::string("bad_") + c.name);
      fs::remove_all(out);
      const fs::path prm =
          write(std::string("bad_") + c.name + ".prm", tiny_prm(out, c.extra));
      const auto r = run_demfem("calibrate " + prm.string());
      INFO(r.out);
      CHECK(r.exit_code != 0);
      CHECK(r.out.find(c.expect1) != std::string::npos);
      if (std::string(c.name) != "unknown")
        {
          CHECK(r.out.find(c.expect2) != std::string::npos);
          CHECK(r.out.find(prm.string()) != std::string::npos); // names the file
        }
      CHECK_FALSE(fs::exists(out));
    }
  // --set with a value outside the physical range names the key too.
  const fs::path out = work_dir() / "bad_set";
  const fs::path prm = write("ok.prm", tiny_prm(out));
  const auto r = run_demfem("calibrate " + prm.string() + " --set \"Vessel/height=-1\"");
  CHECK(r.exit_code != 0);
  CHECK(r.out.find("Vessel/height") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("calibrate: bonded and gapped fractions that add up to one are accepted",
          "[calibrate]")
{
  // 1 - 0.9 is below 0.1 in binary: the range of the gapped fraction is
  // [0, 1 - B] up to round-off, so B 0.9 with G 0.1 (no slits) is the
  // material asked for, not an error.
  const auto t = run_tiny(
      "bonded_gapped", "--set \"Problem/vtk=false\" --set \"Tests/tests=direct tension\""
                       " --set \"Material/Flat joint/bonded fraction=0.9\""
                       " --set \"Material/Flat joint/gapped fraction=0.1\""
                       " --set \"Material/Flat joint/gap mean=1e-6\"");
  INFO(t.r.out);
  REQUIRE(t.r.exit_code == 0);
  const auto  m  = nlohmann::json::parse(read(t.out / "material.json"));
  const auto &mp = m.at("microparameters");
  CHECK(mp.at("fj_B").get<double>() == 0.9);
  CHECK(mp.at("fj_G").get<double>() == 0.1);
}

TEST_CASE("calibrate: a specimen with a smooth-jointed interface is weaker",
          "[calibrate][joint]")
{
  // fistPkg §2.8: a frictional joint inclined at 60 degrees to the loading
  // axis (dip 30: n_j = (sin 30, cos 30)) through the centre; mu = 0.2
  // (11 degrees) is below the plane's inclination to the load, so the
  // joint slips before the bonded material fails: lower UCS than intact.
  auto ucs = [](const std::string &name, bool joint) {
    const fs::path out = work_dir() / name;
    fs::remove_all(out);
    std::string prm = tiny_prm(out);
    prm += "subsection Joint\n  set enabled = " + std::string(joint ? "true" : "false") +
           "\n  set dip = 30\n  set friction = 0.2\n  set normal stiffness = 4e13\n"
           "  set shear stiffness = 2e13\nend\n";
    const auto p = write(name + ".prm", prm);
    const auto r = run_demfem("calibrate " + p.string() + " --set \"Tests/tests=ucs\"");
    INFO(r.out);
    REQUIRE(r.exit_code == 0);
    if (joint)
      CHECK_THAT(r.out, Catch::Contains("smooth joint inserted at"));
    return json_numbers(read(out / "material.json"))["ucs"];
  };
  const double intact  = ucs("intact", false);
  const double jointed = ucs("jointed", true);
  WARN("UCS intact " << intact << " Pa, jointed " << jointed << " Pa");
  CHECK(intact > 0);
  CHECK(jointed < 0.8 * intact);
}

TEST_CASE("calibrate: triaxial series with envelope, rate check and region tension",
          "[calibrate][envelope]")
{
  // Three confining pressures on the tiny material, each test on a copy of
  // one packing; the unconfined one at half rate as well. At this fast,
  // not quasi-static rate (2/s on 150 grains) the rigid walls lag the
  // specimen's dilation by up to about 9 %, beyond the default 1 % that a
  // calibration is held to (status confinement_not_held, tested below):
  // the tolerance of 20 % lets the run end ok, the envelope is what this
  // test checks.
  const fs::path out = work_dir() / "series_out";
  fs::remove_all(out);
  const fs::path prm = write("series.prm", tiny_prm(out));
  const auto     r   = run_demfem("calibrate " + prm.string() +
                                  " --set \"Tests/tests=triaxial series, direct tension\""
                                        " --set \"Tests/confining pressures=0, 2e6, 5e6\""
                                        " --set \"Tests/confining tolerance=0.2\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto mat = nlohmann::json::parse(read(out / "material.json"));
  const auto sum = nlohmann::json::parse(read(out / "summary.json"));
  REQUIRE(mat.contains("envelope"));
  const auto &e  = mat["envelope"];
  const auto  s3 = e["confining_pressures_Pa"].get<std::vector<double>>();
  const auto  s1 = e["peak_axial_stresses_Pa"].get<std::vector<double>>();
  REQUIRE(s3 == std::vector<double>{0, 2e6, 5e6});
  // Confinement strengthens the material: peaks rise with Pc, a positive
  // friction angle and a positive m_i.
  CHECK(s1[1] > s1[0]);
  CHECK(s1[2] > s1[1]);
  CHECK(e["mohr_coulomb"]["friction_angle_deg"].get<double>() > 0);
  CHECK(e["mohr_coulomb"]["cohesion_Pa"].get<double>() > 0);
  CHECK(e["hoek_brown"]["mi"].get<double>() > 0);
  // The series' unconfined test is the material's UCS.
  CHECK(mat["ucs"].get<double>() == s1[0]);
  // Every confined test reports how well the servo held Pc, here within
  // the 20 % given (the run ended ok); the servo's accuracy itself:
  // tests/dem/confined_test.cc.
  for (const auto &t : sum["tests"]["triaxial_series"]["tests"])
    if (t["Pc_Pa"].get<double>() > 0)
      {
        const double d = t["confining_deviation_to_peak"].get<double>();
        CHECK(d >= 0);
        CHECK(d <= 0.2);
      }
  // Direct tension also from the measurement regions (fistPkg §5.7).
  CHECK(mat["direct_tension_regions"].get<double>() > 0);
  CHECK(fs::is_regular_file(out / "envelope.svg"));
  CHECK(fs::is_regular_file(out / "history_triaxial_series_5_MPa.csv"));
}

TEST_CASE(
    "calibrate: a triaxial series over packings fits the envelope to the seed means",
    "[calibrate][envelope][seeds]")
{
  // Problem/seeds = 2: the file's envelope must be the material's, fitted
  // to each confining pressure's mean peak, not the first packing's.
  const auto t =
      run_tiny("series_seeds", "--set \"Tests/tests=triaxial series\" --set "
                               "\"Tests/confining pressures=0, 2e6, 5e6\" "
                               "--set Problem/seeds=2 --set Problem/vtk=false "
                               "--set \"Tests/confining tolerance=0.2\""); // as above
  INFO(t.r.out);
  REQUIRE(t.r.exit_code == 0);
  const auto m  = nlohmann::json::parse(read(t.out / "material.json"));
  const auto a  = nlohmann::json::parse(read(t.out / "seed_10000" / "material.json"));
  const auto b  = nlohmann::json::parse(read(t.out / "seed_10001" / "material.json"));
  const auto pa = a["envelope"]["peak_axial_stresses_Pa"].get<std::vector<double>>();
  const auto pb = b["envelope"]["peak_axial_stresses_Pa"].get<std::vector<double>>();
  REQUIRE(pa.size() == 3);
  REQUIRE(pb.size() == 3);
  CHECK(pa != pb); // two packings (else the comparison below proves nothing)
  const auto         &e  = m["envelope"];
  std::vector<double> s3 = e["confining_pressures_Pa"], s1 = e["peak_axial_stresses_Pa"];
  CHECK(s3 == std::vector<double>{0, 2e6, 5e6});
  for (std::size_t k = 0; k < 3; ++k)
    {
      // Mean and sample standard deviation of two values, to round-off.
      CHECK(s1[k] == Approx(0.5 * (pa[k] + pb[k])).epsilon(1e-12));
      CHECK(e["peak_axial_stresses_sd_Pa"][k].get<double>() ==
            Approx(std::abs(pa[k] - pb[k]) / std::sqrt(2.0)).epsilon(1e-9));
    }
  // Both envelopes are the fits to those means (dem/specimen/envelope.h,
  // tested against closed forms in tests/dem/envelope_test.cc).
  const auto hb = demfem::dem::fit_hoek_brown(s3, s1, "test");
  const auto mc = demfem::dem::fit_mohr_coulomb(s3, s1, "test");
  CHECK(e["hoek_brown"]["mi"].get<double>() == Approx(hb.mi).epsilon(1e-12));
  CHECK(e["hoek_brown"]["sigma_ci_Pa"].get<double>() ==
        Approx(hb.sigma_ci).epsilon(1e-12));
  CHECK(e["mohr_coulomb"]["cohesion_Pa"].get<double>() ==
        Approx(mc.cohesion).epsilon(1e-12));
  // Each packing's own fit is kept, with its mean and scatter.
  const double ma = a["envelope"]["hoek_brown"]["mi"],
               mb = b["envelope"]["hoek_brown"]["mi"];
  CHECK(m["seed_values"]["envelope"]["mi"] == nlohmann::json::array({ma, mb}));
  CHECK(e["seed_mean_of_each_packing_fit"]["mi"].get<double>() ==
        Approx(0.5 * (ma + mb)).epsilon(1e-12));
  CHECK(m["seed_scatter"]["envelope"]["mi"].get<double>() ==
        Approx(std::abs(ma - mb) / std::sqrt(2.0)).epsilon(1e-9));
  // The series' unconfined peak is the UCS: the file's UCS is its mean.
  CHECK(m["ucs"].get<double>() == Approx(s1[0]).epsilon(1e-12));
  CHECK(fs::is_regular_file(t.out / "envelope.svg"));
}

TEST_CASE("calibrate: the confining servo's velocity limit, automatic or given",
          "[calibrate]")
{
  // The loading servo's limit (docs/calibrate.md, "Confining servo"):
  // automatic, the larger of 10 x strain rate x height (10 x 2/s x 0.03 m
  // = 0.6 m/s for the tiny specimen), 2 P_c / (rho c) with c = sqrt(E* /
  // rho) (1.2 m/s at P_c 6 MPa, E* 40 GPa, rho 2650) and 2 |sigma_a| /
  // (rho c) of the step's axial stress, reported at the peak: there the
  // last; or Tests/servo velocity limit, reported as used.
  // (The fast rate's lag of the walls, about 3 %, is allowed: the limit is
  // what is checked.)
  const std::string triaxial =
      tiny_triaxial +
      " --set \"Material/density=2650\" --set \"Tests/confining tolerance=0.2\"";
  const auto automatic = run_tiny("servo_auto", triaxial);
  INFO(automatic.r.out);
  REQUIRE(automatic.r.exit_code == 0);
  const auto t0 = triaxial_summary(automatic);
  // The limit of the peak step is set from the step before it: the axial
  // stress moves by far less than 1e-4 of itself in one step.
  const double impedance = std::sqrt(40e9 * 2650);
  REQUIRE(t0["peak_Pa"].get<double>() > 6e6);
  CHECK(t0["confining_velocity_limit_m_s"].get<double>() ==
        Approx(2 * t0["peak_Pa"].get<double>() / impedance).epsilon(1e-4));
  CHECK(t0["lateral_wall_segments"].get<double>() == 1);
  CHECK(t0["confining_deviation_to_peak"].get<double>() >= 0);
  const auto given =
      run_tiny("servo_given", triaxial + " --set \"Tests/servo velocity limit=3\"");
  INFO(given.r.out);
  REQUIRE(given.r.exit_code == 0);
  const auto t1 = triaxial_summary(given);
  CHECK(t1["confining_velocity_limit_m_s"].get<double>() == 3.0);
  // Refused where it enters, naming the key; nothing written.
  const auto bad =
      run_tiny("servo_bad", triaxial + " --set \"Tests/servo velocity limit=-1\"");
  CHECK(bad.r.exit_code != 0);
  CHECK(bad.r.out.find("Tests/servo velocity limit") != std::string::npos);
  CHECK_FALSE(fs::exists(bad.out));
}

TEST_CASE("calibrate: flexible lateral walls, reported and recorded; bad counts refused",
          "[calibrate]")
{
  // Tests/lateral wall segments (docs/calibrate.md, "Confining servo"):
  // the count used is in each confined test's summary and in the material
  // file's lab_tests; below 1 it is refused where it enters, above what
  // the specimen's height holds at two grain diameters per facet when the
  // test starts, naming the key and the allowed range. (Two facets at this
  // fast rate let P_c deviate by about 9 %: allowed, the record is what is
  // checked.)
  const std::string triaxial = tiny_triaxial + " --set \"Tests/confining tolerance=0.2\"";
  const auto        flex =
      run_tiny("flex_walls", triaxial + " --set \"Tests/lateral wall segments=2\"");
  INFO(flex.r.out);
  REQUIRE(flex.r.exit_code == 0);
  const auto t = triaxial_summary(flex);
  CHECK(t["lateral_wall_segments"].get<double>() == 2);
  CHECK(t["confining_deviation_to_peak"].get<double>() >= 0);
  const auto m = nlohmann::json::parse(read(flex.out / "material.json"));
  CHECK(m["lab_tests"]["lateral_wall_segments"].get<double>() == 2);
  CHECK(m["lab_tests"]["servo_velocity_limit_m_s"].get<double>() == 0);

  const auto zero =
      run_tiny("flex_zero", triaxial + " --set \"Tests/lateral wall segments=0\"");
  CHECK(zero.r.exit_code != 0);
  CHECK(zero.r.out.find("lateral wall segments") != std::string::npos);
  CHECK_FALSE(fs::exists(zero.out / "material.json"));
  const auto many =
      run_tiny("flex_many", triaxial + " --set \"Tests/lateral wall segments=1000\"");
  CHECK(many.r.exit_code != 0);
  CHECK(many.r.out.find("lateral wall segments = 1000") != std::string::npos);
  CHECK(many.r.out.find("allowed for this specimen: 1 to") != std::string::npos);
  CHECK_FALSE(fs::exists(many.out / "material.json"));
}

TEST_CASE("calibrate: a confined test whose P_c was not held is not ok", "[calibrate]")
{
  // Tests/confining tolerance (docs/calibrate.md, "Confining boundary"): a
  // triaxial peak at a confinement that deviated from P_c by more than the
  // tolerance (averaged over a wave's crossing time, up to the peak) is not
  // the strength at P_c: status confinement_not_held, exit 3, the results
  // still written. The tolerance does not change the test itself (the runs
  // are deterministic), so the deviation measured with a tolerance of 1
  // (100 %, accepted) is the one judged with half of it.
  const std::string triaxial = tiny_triaxial;
  const auto        loose =
      run_tiny("held_loose", triaxial + " --set \"Tests/confining tolerance=1\"");
  INFO(loose.r.out);
  REQUIRE(loose.r.exit_code == 0);
  const auto   t0 = triaxial_summary(loose);
  const double d  = t0["confining_deviation_to_peak"].get<double>();
  // Rigid walls at this fast rate lag behind the specimen's dilation by a
  // measurable amount (else the second run below proves nothing).
  REQUIRE(d > 1e-4);
  REQUIRE(d < 0.5);
  std::ostringstream tol;
  tol.precision(17);
  tol << 0.5 * d;
  const auto strict = run_tiny(
      "held_strict", triaxial + " --set \"Tests/confining tolerance=" + tol.str() + "\"");
  INFO(strict.r.out);
  CHECK(strict.r.exit_code == 3);
  CHECK(strict.r.out.find("more than Tests/confining tolerance") != std::string::npos);
  const auto sum = nlohmann::json::parse(read(strict.out / "summary.json"));
  CHECK(sum["status"] == "confinement_not_held");
  CHECK(sum["tests"]["triaxial"]["confining_deviation_to_peak"].get<double>() == d);
  const auto manifest = nlohmann::json::parse(read(strict.out / "manifest.json"));
  CHECK(manifest["status"] == "confinement_not_held");
  CHECK(manifest["exit_code"] == 3);
  const auto m = nlohmann::json::parse(read(strict.out / "material.json"));
  CHECK(m["lab_tests"]["confining_tolerance"].get<double>() ==
        Approx(0.5 * d).epsilon(1e-15));
  // The pressure boundary holds P_c to round-off: ok at the default 1 %.
  const auto pressure = run_tiny(
      "held_pressure", triaxial + " --set \"Tests/confining boundary=pressure\"");
  INFO(pressure.r.out);
  CHECK(pressure.r.exit_code == 0);
  // Refused where it enters, naming the key; nothing written.
  check_refused("tolerance_zero", " --set \"Tests/confining tolerance=0\"",
                "Tests/confining tolerance");
  check_refused("tolerance_big", " --set \"Tests/confining tolerance=1.5\"",
                "Tests/confining tolerance");
}

TEST_CASE("calibrate: the loading-rate check reports half and quarter rate",
          "[calibrate]")
{
  const fs::path out = work_dir() / "rate_out";
  fs::remove_all(out);
  const fs::path prm = write("rate.prm", tiny_prm(out));
  const auto     r   = run_demfem("calibrate " + prm.string() +
                                  " --set \"Tests/tests=ucs\" --set \"Problem/vtk=false\""
                                        " --set \"Tests/loading rate check=quarter\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto   sum = nlohmann::json::parse(read(out / "summary.json"));
  const auto  &u   = sum["tests"]["ucs"];
  const double p = u["peak_Pa"], h = u["peak_half_rate_Pa"],
               q = u["peak_quarter_rate_Pa"];
  CHECK(u["peak_relative_change_half_rate"].get<double>() == Approx((h - p) / p));
  CHECK(u["peak_relative_change_quarter_rate"].get<double>() == Approx((q - p) / p));
  // The flag follows the 2 % rule.
  const bool moved = std::abs(h - p) > 0.02 * p || std::abs(q - p) > 0.02 * p;
  CHECK(u["quasi_static"].get<std::string>() == (moved ? "no" : "yes"));
}

TEST_CASE("calibrate: a test stopped by the step limit is not ok", "[calibrate]")
{
  // 300 loading steps end the UCS test long before its peak (about 10 000
  // steps at this rate): a warning naming the key, status and exit 3, the
  // results still written.
  const auto [out, r] = run_tiny("step_limit", "--set \"Tests/tests=ucs\" --set "
                                               "\"Problem/vtk=false\" --set \"Tests/step "
                                               "limit=300\"");
  INFO(r.out);
  CHECK(r.exit_code == 3);
  CHECK(r.out.find("Tests/step limit") != std::string::npos);
  const auto sum = nlohmann::json::parse(read(out / "summary.json"));
  CHECK(sum["status"] == "step_limit_reached");
  CHECK(sum["tests"]["ucs"]["ended_by"] == "step limit");
  // The manifest records the same status and exit code.
  const auto manifest = nlohmann::json::parse(read(out / "manifest.json"));
  CHECK(manifest["status"] == "step_limit_reached");
  CHECK(manifest["exit_code"] == 3);
  CHECK(fs::is_regular_file(out / "material.json"));
}

TEST_CASE("calibrate: a peak at the strain limit is said to be no strength",
          "[calibrate]")
{
  // A strain limit of 1e-4 stops the UCS test in its elastic range (its
  // peak lies near 1e-3 at this rate): the load is still rising, so the
  // run warns that the peak is no strength. E and nu are measured, so the
  // run stays ok.
  const auto [out, r] =
      run_tiny("strain_limit", "--set \"Tests/tests=ucs\" --set "
                               "\"Problem/vtk=false\" --set \"Tests/strain "
                               "limit=1e-4\"");
  INFO(r.out);
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("with its load still rising") != std::string::npos);
  const auto sum = nlohmann::json::parse(read(out / "summary.json"));
  CHECK(sum["tests"]["ucs"]["ended_by"] == "strain limit");
}

TEST_CASE("calibrate: the run owns its output directory", "[calibrate]")
{
  // manifest.json records the run; a second run into the same directory is
  // refused naming --overwrite, which replaces the results.
  const fs::path out = work_dir() / "owned_out";
  fs::remove_all(out);
  const std::string cmd =
      "calibrate " + write("owned.prm", tiny_prm(out)).string() +
      " --set \"Tests/tests=direct tension\" --set \"Problem/vtk=false\"";
  const auto r1 = run_demfem(cmd);
  INFO(r1.out);
  REQUIRE(r1.exit_code == 0);
  const auto manifest = nlohmann::json::parse(read(out / "manifest.json"));
  CHECK(manifest["status"] == "ok");
  const auto r2 = run_demfem(cmd);
  CHECK(r2.exit_code != 0);
  CHECK(r2.out.find("--overwrite") != std::string::npos);
  const auto r3 = run_demfem(cmd + " --overwrite");
  INFO(r3.out);
  CHECK(r3.exit_code == 0);
  CHECK(fs::is_regular_file(out / "material.json"));
}

TEST_CASE("calibrate: a Brazilian disk that splits gives the BTS",
          "[calibrate][brazilian]")
{
  // A finer disk (about 270 grains, 25 across) of narrow tensile strength
  // (20 +- 2 MPa) and high cohesion splits along its loaded diameter
  // (measured: 35 of its 49 failure cracks in the split zone, 0.71): exit 0,
  // the BTS and its failure mode in material.json and summary.json.
  const auto [out, r] =
      run_splitting("split", " --set \"Vessel/width=0.04\" --set \"Vessel/height=0.04\""
                             " --set \"Material/number of grains=350\""
                             " --set \"Tests/tests=brazilian, direct tension\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("did not split") == std::string::npos);
  const auto  mat = nlohmann::json::parse(read(out / "material.json"));
  const auto  sum = nlohmann::json::parse(read(out / "summary.json"));
  const auto &b   = sum["tests"]["brazilian"];
  CHECK(sum["status"] == "ok");
  CHECK(b["failure_mode"] == "split");
  CHECK(b["split_fraction"].get<double>() >= 0.5);
  CHECK(b["failure_cracks"].get<double>() > 0);
  CHECK(mat["bts_failure_mode"] == "split");
  CHECK(mat["bts_split_fraction"].get<double>() == b["split_fraction"].get<double>());
  // The BTS is the test's Eq. 24 peak; the ratio uses it.
  CHECK(mat["bts"].get<double>() == b["peak_Pa"].get<double>());
  CHECK(mat["bts"].get<double>() > 0);
  CHECK(mat["ratios"]["direct_tension_to_bts"].get<double>() ==
        Approx(mat["direct_tension"].get<double>() / mat["bts"].get<double>())
            .epsilon(1e-12));
}

TEST_CASE("calibrate: a flattened Brazilian disk", "[calibrate][brazilian]")
{
  // The disk of the split test above with flats of 2 alpha = 20 deg
  // (Tests/brazilian flat angle): the BTS is k F / (pi R t) with the
  // arc-load factor k = sin 2 alpha / alpha - 1 = 0.9596 from the summary's
  // force, radius and thickness; the angle is recorded in material.json for
  // the probe; out of its range (0 .. 20) it is refused naming the key and
  // nothing is written.
  const auto [out, r] = run_splitting(
      "flat_disk",
      " --set \"Vessel/width=0.04\" --set \"Vessel/height=0.04\""
      " --set \"Material/number of grains=350\""
      " --set \"Tests/tests=brazilian\" --set \"Tests/brazilian flat angle=20\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto  mat = nlohmann::json::parse(read(out / "material.json"));
  const auto  sum = nlohmann::json::parse(read(out / "summary.json"));
  const auto &b   = sum["tests"]["brazilian"];
  CHECK(b["failure_mode"] == "split");
  const double k = std::sin(M_PI / 9) / (M_PI / 18) - 1;
  CHECK(b["peak_Pa"].get<double>() ==
        Approx(k * b["peak_force_N"].get<double>() /
               (M_PI * b["disk_radius_m"].get<double>() * b["thickness_m"].get<double>()))
            .epsilon(1e-12));
  CHECK(mat["bts"].get<double>() == b["peak_Pa"].get<double>());
  CHECK(mat["lab_tests"]["brazilian_flat_angle_deg"].get<double>() == 20);

  check_refused("flat_angle", " --set \"Tests/brazilian flat angle=25\"",
                "Tests/brazilian flat angle", "allowed");
}

TEST_CASE("calibrate: a Brazilian specimen of its own, packed at the grain size",
          "[calibrate][brazilian]")
{
  // Tests/brazilian diameter packs the disk in a box of its own, at the
  // grain size of the 15 x 30 mm specimen: the grain-scaling genesis draws
  // the grains for the vessel's area at the cloud porosity, so 40 x 40 mm
  // holds 1600 / 450 times its grains (measured 536 for 151: 536.9; 2 %
  // allows the rounding of the draws). The disk is then 40 mm across, not
  // the 15 mm of the vessel's width, about 22 grains instead of 8, and with
  // the split test's narrow strengths it splits (measured 0.67 of 51
  // failure cracks in the split zone).
  const auto [out, r] =
      run_splitting("own_disk", " --set \"Tests/brazilian diameter=0.04\""
                                " --set \"Tests/tests=ucs, brazilian\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("genesis of the Brazilian specimen (0.04 m across)") !=
        std::string::npos);
  const auto   mat        = nlohmann::json::parse(read(out / "material.json"));
  const auto   sum        = nlohmann::json::parse(read(out / "summary.json"));
  const auto  &b          = sum["tests"]["brazilian"];
  const double n_disk_box = sum["brazilian_n_grains"].get<double>();
  CHECK(n_disk_box ==
        Approx(sum["n_grains"].get<double>() * 1600.0 / 450.0).epsilon(0.02));
  // The disk's radius is the extent of the grains inside R = 20 mm: within
  // a grain diameter (at most 1.6 mm x the grain-scaling factor, < 2.5 mm;
  // measured 19.1 mm).
  CHECK(b["disk_radius_m"].get<double>() <= 0.02 + 1e-12);
  CHECK(b["disk_radius_m"].get<double>() > 0.02 - 2.5e-3);
  CHECK(b["failure_mode"] == "split");
  CHECK(mat["bts"].get<double>() == b["peak_Pa"].get<double>());
  // Recorded for the probe, which repeats the test at the region's scale.
  CHECK(mat["lab_tests"]["brazilian_diameter_m"].get<double>() == 0.04);
  CHECK(mat["lab_tests"]["brazilian_thickness_m"].get<double>() == 0);
  // Its checkpoint is scratch, removed like the specimen's.
  CHECK_FALSE(fs::exists(out / "specimen_brazilian.h5"));

  // A thickness is a 3D key: refused in 2D naming it, nothing written.
  check_refused("disk_thickness",
                " --set \"Tests/brazilian diameter=0.04\""
                " --set \"Tests/brazilian thickness=0.02\"",
                "Tests/brazilian thickness");
  check_refused("disk_diameter", " --set \"Tests/brazilian diameter=-1\"",
                "Tests/brazilian diameter");
}

TEST_CASE("calibrate: a Brazilian disk that does not split gives no BTS",
          "[calibrate][brazilian]")
{
  // Unbreakable joints and a strain limit of 1e-3: the disk never fails,
  // the test ends at the strain limit with no crack, and its peak is no
  // tensile strength (docs/calibrate.md, "Failure mode of the Brazilian
  // test"): a warning naming the test and why, status
  // brazilian_not_split, exit 3, bts null; the other results are written.
  const fs::path out = work_dir() / "not_split_out";
  fs::remove_all(out);
  const fs::path prm = write("not_split.prm", tiny_prm(out));
  const auto     r   = run_demfem("calibrate " + prm.string() +
                                  " --set \"Tests/tests=brazilian\" --set \"Problem/vtk=false\""
                                        " --set \"Tests/strain limit=1e-3\""
                                        " --set \"Material/Flat joint/tensile strength mean=1e12\""
                                        " --set \"Material/Flat joint/cohesion mean=1e12\"");
  INFO(r.out);
  CHECK(r.exit_code == 3);
  CHECK(r.out.find("warning: brazilian did not split along the loaded diameter") !=
        std::string::npos);
  CHECK(r.out.find("no crack formed after the peak") != std::string::npos);
  const auto sum = nlohmann::json::parse(read(out / "summary.json"));
  CHECK(sum["status"] == "brazilian_not_split");
  const auto &b = sum["tests"]["brazilian"];
  CHECK(b["ended_by"] == "strain limit");
  CHECK(b["failure_mode"] == "no_failure");
  CHECK(b["failure_cracks"] == 0);
  CHECK(b["split_fraction"].is_null());
  CHECK(b["peak_Pa"].get<double>() > 0); // the load is still reported
  const auto mat = nlohmann::json::parse(read(out / "material.json"));
  CHECK(mat["bts"].is_null());
  CHECK(mat["bts_failure_mode"] == "no_failure");
  CHECK(mat["ratios"]["ucs_to_bts"].is_null());
  const auto manifest = nlohmann::json::parse(read(out / "manifest.json"));
  CHECK(manifest["status"] == "brazilian_not_split");
  CHECK(manifest["exit_code"] == 3);

  // The threshold is checked where it enters, naming the key and range.
  check_refused("split_fraction", " --set \"Tests/brazilian split fraction=0\"",
                "Tests/brazilian split fraction", "allowed range");
}

TEST_CASE("calibrate: the pressure boundary, reported and recorded; refused in 3D and "
          "with flexible walls",
          "[calibrate]")
{
  // Tests/confining boundary = pressure (docs/calibrate.md, "Confining
  // boundary"): each confined test's summary names its boundary and holds
  // P_c to round-off (the applied forces); the material file's lab_tests
  // records the choice; where it cannot apply it is refused where it
  // enters, naming the key and what is allowed, and nothing is written.
  const std::string triaxial =
      tiny_triaxial + " --set \"Tests/confining boundary=pressure\"";
  const auto pb = run_tiny("pressure_boundary", triaxial);
  INFO(pb.r.out);
  REQUIRE(pb.r.exit_code == 0);
  const auto t = triaxial_summary(pb);
  CHECK(t["confining_boundary"].get<std::string>() == "pressure");
  CHECK(t["confining_deviation_to_peak"].get<double>() < 1e-9);
  CHECK(t["peak_Pa"].get<double>() > 6e6);
  const auto m = nlohmann::json::parse(read(pb.out / "material.json"));
  CHECK(m["lab_tests"]["confining_boundary"].get<std::string>() == "pressure");

  const auto flex =
      run_tiny("pressure_flex", triaxial + " --set \"Tests/lateral wall segments=2\"");
  CHECK(flex.r.exit_code != 0);
  CHECK(flex.r.out.find("Tests/lateral wall segments = 2") != std::string::npos);
  CHECK(flex.r.out.find("confining boundary = pressure: 1") != std::string::npos);
  CHECK_FALSE(fs::exists(flex.out / "material.json"));
  const auto three = run_tiny("pressure_3d", triaxial + " --set \"Problem/dimension=3\"");
  CHECK(three.r.exit_code != 0);
  CHECK(three.r.out.find("Tests/confining boundary = pressure: 2D only") !=
        std::string::npos);
  CHECK_FALSE(fs::exists(three.out / "material.json"));
}
