// `demfem calibrate` with Voronoi grains (Material/type = rigid-voronoi |
// flexible-voronoi, docs/calibrate.md "Voronoi grains"): the example runs and
// writes a complete material.json, VTK and a manifest; bad keys and the
// options the Voronoi grains do not have are refused naming the key and the
// file, writing nothing; a test stopped by its step limit exits 3.
#include "run_command.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>
#include <vtkCellData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <cmath>
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
        fs::temp_directory_path() /
        ("demfem_calibrate_voronoi_test_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }

  std::string read(const fs::path &p)
  {
    std::ifstream     f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }

  const std::string example =
      std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/voronoi_rigid_2d.prm";

  // The example into `out` with extra --set overrides.
  demfem::testing::CommandResult run_example(const fs::path    &out,
                                             const std::string &sets = "")
  {
    return run_demfem("calibrate " + example +
                      " --set \"Problem/output directory=" + out.string() + "\" " + sets);
  }

  // A VTK XML PolyData file read back as ParaView reads it.
  vtkSmartPointer<vtkPolyData> read_vtp(const fs::path &path)
  {
    vtkNew<vtkXMLPolyDataReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    return r->GetOutput();
  }
} // namespace

TEST_CASE("calibrate voronoi: the rigid example end to end", "[calibrate][voronoi]")
{
  const fs::path out = work_dir() / "example";
  fs::remove_all(out);
  const auto r = run_example(out);
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto mat = nlohmann::json::parse(read(out / "material.json"));
  // Finite elastic constants and strengths, each test's own.
  for (const char *k :
       {"E", "nu", "E_plane_stress", "nu_plane_stress", "ucs", "bts", "direct_tension"})
    {
      INFO(k);
      REQUIRE(mat[k].is_number());
      CHECK(std::isfinite(mat[k].get<double>()));
    }
  const double E = mat["E"], nu = mat["nu"], Eps = mat["E_plane_stress"],
               nups = mat["nu_plane_stress"];
  // kappa = 1.5: nu' > 0 and E' < E_c = 50 GPa (docs/voronoi.md: 0.918 E_c,
  // nu' = 0.090 at 0.25/s); the plane-strain pair follows from it.
  CHECK(Eps > 0.8 * 50e9);
  CHECK(Eps < 50e9);
  CHECK(nups > 0.02);
  CHECK(nups < 0.2);
  CHECK(nu == Approx(nups / (1 + nups)).epsilon(1e-12));
  CHECK(E == Approx(Eps * (1 - nu * nu)).epsilon(1e-12));
  // A rock-like order: UCS well above the tensile strengths.
  const double ucs = mat["ucs"], bts = mat["bts"], dt = mat["direct_tension"];
  CHECK(ucs > 0);
  CHECK(bts > 0);
  CHECK(dt > 0);
  CHECK(ucs > 3 * dt);
  CHECK(ucs > 3 * bts);
  // Post-peak brittleness, recomputed from the UCS history: the strain
  // from the peak to the first row below 0.9 of it, over the peak strain.
  {
    std::istringstream csv(read(out / "history_ucs.csv"));
    std::string        line;
    std::getline(csv, line);
    std::vector<double> e, q;
    while (std::getline(csv, line))
      {
        std::vector<double> v;
        std::stringstream   row(line);
        for (std::string c; std::getline(row, c, ',');)
          v.push_back(std::stod(c));
        e.push_back(std::abs(v[2])), q.push_back(std::abs(v[4]));
      }
    const auto peak = std::max_element(q.begin(), q.end()) - q.begin();
    const auto drop = std::find_if(q.begin() + peak, q.end(),
                                   [&](double x) { return x < 0.9 * q[peak]; }) -
                      q.begin();
    REQUIRE(drop < long(q.size()));
    const double ratio = mat["ratios"]["post_peak_strain_ratio"];
    // The CSV holds 10 digits: the difference of two strains keeps ~1e-7.
    CHECK(ratio == Approx((e[drop] - e[peak]) / e[peak]).epsilon(1e-6));
    CHECK(ratio > 0);
  }
  CHECK(mat["microparameters"]["type"] == "rigid-voronoi");
  CHECK(mat["microparameters"]["contact_modulus_Pa"] == 50e9);
  CHECK(mat["microparameters"]["stiffness_ratio"] == 1.5);
  CHECK(mat["microparameters"]["tensile_strength_Pa"] == 2.5e6);
  // Histories, the manifest and VTK of cells, points, cracks per test.
  const auto sum = nlohmann::json::parse(read(out / "summary.json"));
  CHECK(sum["status"] == "ok");
  const auto manifest = nlohmann::json::parse(read(out / "manifest.json"));
  CHECK(manifest["status"] == "ok");
  CHECK(manifest["exit_code"] == 0);
  for (const char *t : {"ucs", "brazilian", "direct_tension"})
    {
      INFO(t);
      const std::string csv = read(out / (std::string("history_") + t + ".csv"));
      CHECK(csv.rfind("step,time_s,axial_strain", 0) == 0);
      CHECK(std::count(csv.begin(), csv.end(), '\n') > 20);
      const auto base   = out / "vtk" / (std::string(t) + "_end_");
      const auto cells  = read_vtp(base.string() + "cells.vtp");
      const auto points = read_vtp(base.string() + "points.vtp");
      const auto cracks = read_vtp(base.string() + "cracks.vtp");
      // A polygon per grain with its stress; about three contacts of three
      // Lobatto points per grain; every test ended after its peak, so
      // cracks were written, each with its mode.
      const int n_grains = sum["tests"][t]["n_grains"];
      CHECK(cells->GetNumberOfPolys() == n_grains);
      CHECK(cells->GetCellData()->GetArray("stress") != nullptr);
      CHECK(points->GetNumberOfPoints() == sum["tests"][t]["n_points"].get<int>());
      CHECK(points->GetNumberOfPoints() > 6 * n_grains);
      CHECK(cracks->GetNumberOfLines() > 0);
      CHECK(cracks->GetNumberOfLines() ==
            sum["tests"][t]["cracks_tensile_at_end"].get<int>() +
                sum["tests"][t]["cracks_shear_at_end"].get<int>());
      CHECK(cracks->GetCellData()->GetArray("mode") != nullptr);
      CHECK(sum["tests"][t]["ended_by"] == "post-peak");
    }
}

TEST_CASE("calibrate voronoi: bad input is refused naming the key, writing nothing",
          "[calibrate][voronoi]")
{
  struct Case
  {
    const char *name, *sets, *expect1, *expect2;
  };
  const Case cases[] = {
      {"modulus", "--set \"Material/Voronoi/contact modulus=-1\"",
       "Material/Voronoi/contact modulus", "allowed range"},
      {"poisson",
       "--set \"Material/type=flexible-voronoi\" --set \"Tests/tests=ucs\" "
       "--set \"Material/Voronoi/grain poisson ratio=0.5\"",
       "Material/Voronoi/grain poisson ratio", "allowed range"},
      {"fracture energy", "--set \"Material/Voronoi/tensile fracture energy=1e-6\"",
       "Material/Voronoi/tensile fracture energy", "brittle value"},
      {"3D", "--set \"Problem/dimension=3\"", "Material/type", "flatjointed"},
      {"short edges",
       "--set \"Material/type=flexible-voronoi\" "
       "--set \"Material/Voronoi/short edge fraction=0.5\"",
       "Material/Voronoi/short edge fraction", "allowed range"},
      {"uniaxial strain", "--set \"Tests/tests=uniaxial strain\"", "uniaxial strain",
       "allowed"},
      {"sizes",
       "--set \"Material/size distribution=uniform 1e-3 2e-3 0.5; uniform 2e-3 3e-3 "
       "0.5\"",
       "Material/size distribution", "uniform D_lo D_hi 1"},
  };
  for (const auto &c : cases)
    {
      INFO("case " << c.name);
      const fs::path out = work_dir() / (std::string("bad_") + c.name);
      fs::remove_all(out);
      const auto r = run_example(out, c.sets);
      INFO(r.out);
      CHECK(r.exit_code == 1);
      CHECK(r.out.find(c.expect1) != std::string::npos);
      CHECK(r.out.find(c.expect2) != std::string::npos);
      CHECK(r.out.find(example) != std::string::npos); // names the file
      CHECK_FALSE(fs::exists(out));
    }
}

TEST_CASE("calibrate voronoi: a test stopped by the step limit exits 3",
          "[calibrate][voronoi]")
{
  const fs::path out = work_dir() / "step_limit";
  fs::remove_all(out);
  const auto r =
      run_example(out, "--set \"Tests/tests=ucs\" --set \"Tests/step limit=300\"");
  INFO(r.out);
  CHECK(r.exit_code == 3);
  CHECK(r.out.find("Tests/step limit") != std::string::npos);
  const auto sum = nlohmann::json::parse(read(out / "summary.json"));
  CHECK(sum["status"] == "step_limit_reached");
  CHECK(sum["tests"]["ucs"]["ended_by"] == "step limit");
  const auto manifest = nlohmann::json::parse(read(out / "manifest.json"));
  CHECK(manifest["status"] == "step_limit_reached");
  CHECK(manifest["exit_code"] == 3);
  CHECK(fs::is_regular_file(out / "material.json"));
}

TEST_CASE("calibrate voronoi: flexible grains are softer than rigid ones",
          "[calibrate][voronoi]")
{
  // The same contacts with deformable grains: the grains' compliance adds to
  // the contacts' (docs/voronoi.md, "flexible -> rigid"), so E' falls.
  // The UCS in its elastic range only (strain limit 3e-4, the peak is near
  // 7e-4).
  const std::string sets  = "--set \"Tests/tests=ucs\" --set \"Material/number of "
                            "grains=60\" --set \"Tests/strain limit=3e-4\"";
  const fs::path    rigid = work_dir() / "rigid60", flex = work_dir() / "flex60";
  fs::remove_all(rigid);
  fs::remove_all(flex);
  const auto a = run_example(rigid, sets);
  INFO(a.out);
  REQUIRE(a.exit_code == 0);
  const auto b =
      run_example(flex, sets + " --set \"Material/type=flexible-voronoi\""
                               " --set \"Material/Voronoi/grain youngs modulus=50e9\"");
  INFO(b.out);
  REQUIRE(b.exit_code == 0);
  const auto ma = nlohmann::json::parse(read(rigid / "material.json"));
  const auto mb = nlohmann::json::parse(read(flex / "material.json"));
  CHECK(mb["microparameters"]["type"] == "flexible-voronoi");
  const auto sb = nlohmann::json::parse(read(flex / "summary.json"));
  CHECK(sb["status"] == "ok");
  CHECK(sb["tests"]["ucs"]["ended_by"] == "strain limit");
  CHECK(mb["microparameters"]["grain_youngs_modulus_Pa"] == 50e9);
  const double Ea = ma["E_plane_stress"], Eb = mb["E_plane_stress"];
  CHECK(std::isfinite(mb["ucs"].get<double>()));
  CHECK(Eb < 0.9 * Ea);
  CHECK(Eb > 0.2 * Ea);
  // The Brazilian test on flexible grains ends after its peak; deformable
  // grains spread the platen load, so its strength is of the rigid one's
  // order (the library test compares them with stiff grains to 2 %).
  const std::string disk = "--set \"Tests/tests=brazilian\" --set \"Material/number of "
                           "grains=60\"";
  const fs::path    rigid_disk = work_dir() / "rigid60_disk",
                 flex_disk     = work_dir() / "flex60_disk";
  fs::remove_all(rigid_disk);
  fs::remove_all(flex_disk);
  REQUIRE(run_example(rigid_disk, disk).exit_code == 0);
  const auto c = run_example(
      flex_disk, disk + " --set \"Material/type=flexible-voronoi\""
                        " --set \"Material/Voronoi/grain youngs modulus=50e9\"");
  INFO(c.out);
  REQUIRE(c.exit_code == 0);
  const auto sc = nlohmann::json::parse(read(flex_disk / "summary.json"));
  CHECK(sc["tests"]["brazilian"]["ended_by"] == "post-peak");
  const double bts_a = nlohmann::json::parse(read(rigid_disk / "material.json"))["bts"];
  const double bts_b = nlohmann::json::parse(read(flex_disk / "material.json"))["bts"];
  CHECK(bts_b > 0.5 * bts_a);
  CHECK(bts_b < 2 * bts_a);
  // VTK of the element triangles (several per grain), points and cracks.
  for (const auto &[dir, t] : {std::pair{flex, "ucs"}, std::pair{flex_disk, "brazilian"}})
    {
      INFO(t);
      const auto sum   = nlohmann::json::parse(read(dir / "summary.json"));
      const auto base  = dir / "vtk" / (std::string(t) + "_end_");
      const auto cells = read_vtp(base.string() + "cells.vtp");
      const int  n     = sum["tests"][t]["n_grains"];
      CHECK(cells->GetNumberOfPolys() > 3 * n);
      CHECK(cells->GetCellData()->GetArray("grain") != nullptr);
      const auto points = read_vtp(base.string() + "points.vtp");
      CHECK(points->GetNumberOfPoints() == sum["tests"][t]["n_points"].get<int>());
      CHECK(fs::is_regular_file(base.string() + "cracks.vtp"));
    }
}

TEST_CASE("calibrate voronoi: confinement raises the peak", "[calibrate][voronoi]")
{
  // Pc = 1 MPa on the sides (docs/voronoi.md, "Lab tests": the confined
  // peak exceeds UCS + Pc); material.json reports it with its pressure.
  const fs::path out = work_dir() / "triaxial";
  fs::remove_all(out);
  const auto r = run_example(out, "--set \"Tests/tests=ucs, triaxial\" --set "
                                  "\"Tests/confining pressure=1e6\" --set "
                                  "\"Problem/vtk=false\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto   mat = nlohmann::json::parse(read(out / "material.json"));
  const double ucs = mat["ucs"], triaxial = mat["triaxial_strength"];
  CHECK(mat["confining_pressure"] == 1e6);
  CHECK(triaxial > ucs + 1e6);
  const auto sum = nlohmann::json::parse(read(out / "summary.json"));
  CHECK(sum["tests"]["triaxial"]["confining_steps"].get<double>() > 0);
  CHECK(sum["tests"]["triaxial"]["Pc_Pa"] == 1e6);
  CHECK_FALSE(fs::exists(out / "vtk"));
}

namespace
{
  // About 100 rigid grains with unbreakable contacts loaded to an axial
  // strain of 1e-3: the elastic stage's small-strain test and the full UCS
  // test are the same test, so E and nu are one deterministic function of
  // (E_c, kappa) on the fixed packing.
  demfem::testing::CommandResult run_fit(const fs::path &out, double Ec, double kappa,
                                         const std::string &fit)
  {
    std::ostringstream s;
    s.precision(17);
    s << "--fit --set \"Material/number of grains=100\" --set \"Tests/tests=ucs\" "
         "--set \"Tests/strain limit=1e-3\" "
         "--set \"Material/Voronoi/tensile strength=1e12\" "
         "--set \"Material/Voronoi/cohesion=1e12\" "
         "--set \"Material/Voronoi/tensile fracture energy=0\" "
         "--set \"Material/Voronoi/shear fracture energy=0\" "
         "--set \"Material/Voronoi/contact modulus="
      << Ec << "\" --set \"Material/Voronoi/stiffness ratio=" << kappa
      << "\" --set \"Fit/seeds=1\" --set \"Fit/elastic strain=1e-3\" "
         "--set \"Fit/parameters=contact modulus 10e9 100e9; stiffness ratio 1 4\" "
      << fit;
    return run_example(out, s.str());
  }
} // namespace

TEST_CASE("calibrate voronoi --fit recovers known microparameters",
          "[calibrate][voronoi][fit]")
{
  // 1. The properties of the known material E_c = 40 GPa, kappa = 2: one
  //    evaluation at the start point, targets unreachable (exit 3).
  const fs::path out1 = work_dir() / "fit_known";
  fs::remove_all(out1);
  const auto r1 =
      run_fit(out1, 40e9, 2, "--set \"Fit/evaluations=1\" --set \"Fit/Targets/E=1e9\"");
  INFO(r1.out);
  REQUIRE(r1.exit_code == 3);
  CHECK(nlohmann::json::parse(read(out1 / "fit.json"))["status"] ==
        "targets_not_reached");
  CHECK(nlohmann::json::parse(read(out1 / "manifest.json"))["status"] ==
        "targets_not_reached");
  const auto   m1       = nlohmann::json::parse(read(out1 / "material.json"));
  const double E_known  = m1["E"];
  const double nu_known = m1["nu"];
  REQUIRE(m1["microparameters"]["contact_modulus_Pa"].get<double>() == 40e9);

  // 2. Start elsewhere (E_c 25 GPa, kappa 3.2) with those properties as
  //    targets: the search must come back to the known microparameters.
  const fs::path out2 = work_dir() / "fit_search";
  fs::remove_all(out2);
  std::ostringstream t;
  t.precision(17);
  t << "--set \"Fit/evaluations=60\" --set \"Fit/Targets/E=" << E_known
    << ", 1, 0.002\" --set \"Fit/Targets/nu=" << nu_known << ", 1, 0.005\"";
  const auto r2 = run_fit(out2, 25e9, 3.2, t.str());
  INFO(r2.out);
  REQUIRE(r2.exit_code == 0);
  const auto fit = nlohmann::json::parse(read(out2 / "fit.json"));
  CHECK(fit["status"] == "ok");
  CHECK(nlohmann::json::parse(read(out2 / "manifest.json"))["status"] == "ok");
  // E is proportional to E_c at a fixed kappa on a fixed packing, and nu
  // depends on kappa only: the 0.2 % and 0.5 % tolerances leave E_c and
  // kappa within about 1 % and 5 % (nu moves slowly with kappa).
  CHECK(fit["best_parameters"]["contact modulus"].get<double>() ==
        Approx(40e9).epsilon(0.01));
  CHECK(fit["best_parameters"]["stiffness ratio"].get<double>() ==
        Approx(2).epsilon(0.05));
  // The calibrated best material is the one written.
  const auto m2 = nlohmann::json::parse(read(out2 / "material.json"));
  CHECK(m2["microparameters"]["contact_modulus_Pa"].get<double>() ==
        fit["best_parameters"]["contact modulus"].get<double>());
  for (const char *f : {"fit.csv", "fit_convergence.svg", "summary.json"})
    CHECK(fs::is_regular_file(out2 / f));
}

TEST_CASE("calibrate voronoi --fit refuses what it cannot search",
          "[calibrate][voronoi][fit]")
{
  struct Case
  {
    const char *name, *sets, *key;
  };
  const Case cases[] = {
      {"rigid_grain_modulus",
       "--set \"Fit/parameters=grain youngs modulus 10e9 100e9\" "
       "--set \"Fit/Targets/E=30e9\"",
       "grain youngs modulus"},
      {"zero_modulus",
       "--set \"Fit/parameters=contact modulus 0 100e9\" --set \"Fit/Targets/E=30e9\"",
       "Fit/parameters (contact modulus)"},
      {"grain_nu_half",
       "--set \"Material/type=flexible-voronoi\" --set \"Tests/tests=ucs\" "
       "--set \"Fit/parameters=grain poisson ratio 0.1 0.5\" "
       "--set \"Fit/Targets/nu=0.2\"",
       "Fit/parameters (grain poisson ratio)"},
      {"mi_without_series",
       "--set \"Fit/parameters=friction 0.1 1\" --set \"Fit/Targets/mi=20\"",
       "Fit/Targets/mi"},
      {"no_target", "--set \"Fit/parameters=friction 0.1 1\"", "Fit/Targets"}};
  for (const auto &c : cases)
    {
      SECTION(c.name)
      {
        const fs::path out = work_dir() / (std::string("fit_bad_") + c.name);
        fs::remove_all(out);
        const auto r = run_example(out, std::string("--fit ") + c.sets);
        INFO(r.out);
        CHECK(r.exit_code == 1);
        CHECK(r.out.find(c.key) != std::string::npos);
        CHECK(!fs::exists(out));
      }
    }
}

TEST_CASE("calibrate voronoi: the flexible Lac du Bonnet example reproduces its material "
          "file",
          "[calibrate][voronoi]")
{
  // The committed material.json is the output of the example
  // (docs/voronoi.md, "Lac du Bonnet"); its direct tension test (the
  // cheapest of the three, ~5 000 steps) on the same packing gives the same
  // strength. Bit-identical on the development machine; 1 % leaves room for
  // another libm.
  const std::string dir = std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/";
  const fs::path    out = work_dir() / "flexible_ldb";
  fs::remove_all(out);
  const auto r = run_demfem("calibrate " + dir + "voronoi_flexible_ldb_2d.prm" +
                            " --set \"Problem/output directory=" + out.string() +
                            "\" --set \"Tests/tests=direct tension\"");
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const auto committed =
      nlohmann::json::parse(read(dir + "voronoi_flexible_ldb_2d.material.json"));
  const auto now = nlohmann::json::parse(read(out / "material.json"));
  CHECK(now["direct_tension"].get<double>() ==
        Approx(committed["direct_tension"].get<double>()).epsilon(0.01));
  CHECK(now["microparameters"] == committed["microparameters"]);
  // The committed material is the granite of the comparison: E, nu, UCS
  // within 10 % of Lac du Bonnet on this packing, the BTS within its
  // scatter between packings (7.1-11.4 MPa; the 3-packing mean is +8 %),
  // DT below the BTS.
  CHECK(committed["E"].get<double>() == Approx(69e9).epsilon(0.1));
  CHECK(committed["nu"].get<double>() == Approx(0.26).epsilon(0.1));
  CHECK(committed["ucs"].get<double>() == Approx(200e6).epsilon(0.1));
  CHECK(committed["bts"].get<double>() == Approx(8.8e6).epsilon(0.2));
  CHECK(committed["direct_tension"].get<double>() < committed["bts"].get<double>());
}
