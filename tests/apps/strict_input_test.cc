// Strict parsing of every value the apps read themselves (docs/tunnel.md,
// "Parameter files and strict input"): trailing characters, a fraction where
// an integer is needed, an empty or key-less file, a directory, a misspelled
// --set section and a bad material file are errors naming the key, where it
// was given and what is allowed; exit 1 and nothing written.
#include "run_command.h"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using demfem::testing::run_demfem;

namespace
{
  fs::path work_dir()
  {
    static const fs::path d =
        fs::temp_directory_path() / ("demfem_strict_input_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }

  std::string example(const std::string &name)
  {
    return std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/" + name;
  }

  std::string read(const fs::path &f)
  {
    std::ifstream     in(f);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  /// Runs `command file args` into a fresh output directory and checks exit
  /// 1, every fragment in the message and that nothing was written.
  void expect_refused(const std::string &command, const std::string &file,
                      const std::string &args, const std::vector<std::string> &fragments)
  {
    const fs::path out = work_dir() / "out";
    fs::remove_all(out);
    const auto r =
        run_demfem(command + " " + file +
                   " --set \"Problem/output directory=" + out.string() + "\" " + args);
    INFO(command << " " << args << "\n" << r.out);
    CHECK(r.exit_code == 1);
    for (const auto &f : fragments)
      CHECK_THAT(r.out, Catch::Contains(f));
    CHECK_FALSE(fs::exists(out));
  }
} // namespace

TEST_CASE("strict input: trailing characters are refused, naming the key",
          "[apps][strict]")
{
  const auto tunnel = example("tunnel_2d.prm");
  expect_refused("tunnel", tunnel, "--set \"DEM region/grain diameter=0.125x\"",
                 {"DEM region/grain diameter", "'0.125x'", "--set", "[m]"});
  expect_refused("tunnel", tunnel, "--set \"DEM region/radius=3.5m\"",
                 {"DEM region/radius", "'3.5m'", "auto"});
  expect_refused("tunnel", tunnel, "--set \"DEM region/grain diameter=0.1 2\"",
                 {"DEM region/grain diameter", "'0.1 2'"});
  // In a file: the message names the file.
  const fs::path prm = work_dir() / "trailing.prm";
  std::ofstream(prm) << "subsection DEM region\n  set grain diameter = 0.125x\nend\n";
  expect_refused("tunnel", prm.string(), "",
                 {"DEM region/grain diameter", "0.125x", prm.string()});
}

TEST_CASE("strict input: study lists refuse fractions, junk and empty entries",
          "[apps][strict]")
{
  const auto study = example("study_2d.prm");
  expect_refused("study", study, "--set \"Study/seeds=1.5\"",
                 {"Study/seeds", "'1.5'", "integer"});
  expect_refused("study", study, "--set \"Study/subcycles=2x\"",
                 {"Study/subcycles", "2x"});
  expect_refused("study", study, "--set \"Study/grain resolutions=4,,6\"",
                 {"Study/grain resolutions", "empty entry"});
  expect_refused("study", study, "--set \"Study/timestep safety factors=0.5,0.8e\"",
                 {"Study/timestep safety factors", "0.8e"});
}

TEST_CASE("strict input: empty file, directory, misspelled section", "[apps][strict]")
{
  const fs::path empty = work_dir() / "empty.prm";
  std::ofstream(empty) << "# only a comment\n\n";
  expect_refused("tunnel", empty.string(), "", {"sets no key", "--defaults"});
  expect_refused("fem", empty.string(), "", {"sets no key", "--defaults"});
  expect_refused("study", empty.string(), "", {"sets no key", "--defaults"});
  expect_refused("tunnel", work_dir().string(), "", {"is a directory"});
  expect_refused("tunnel", example("tunnel_2d.prm"),
                 "--set \"Contnuum/young modulus=1e9\"", {"unknown section 'Contnuum'"});
  expect_refused("fem", example("kirsch_2d.prm"),
                 "--set \"Continuum/youngs modulus=1e9\"", {"youngs modulus"});
}

TEST_CASE("strict input: --defaults runs a key-less file and is documented",
          "[apps][strict]")
{
  const auto help = run_demfem("tunnel --help");
  CHECK(help.exit_code == 0);
  CHECK_THAT(help.out, Catch::Contains("--defaults") && Catch::Contains("--overwrite"));

  const fs::path empty = work_dir() / "empty_fem.prm";
  std::ofstream(empty) << "";
  const fs::path out = work_dir() / "defaults_out";
  fs::remove_all(out);
  // A small continuum so that the defaults run in a second.
  const auto r =
      run_demfem("fem " + empty.string() +
                 " --defaults --set \"Problem/output directory=" + out.string() +
                 "\" --set \"Continuum/element degree=1\" --set "
                 "\"Continuum/outer radius=5\"");
  INFO(r.out);
  CHECK(r.exit_code == 0);
  CHECK(fs::exists(out / "summary.json"));
  fs::remove_all(out);
}

TEST_CASE("strict input: material-file errors name the material file and its key",
          "[apps][strict]")
{
  const std::string text = read(example("lac_du_bonnet_2d.material.json"));
  REQUIRE(text.find("\"seed\": 10000") != std::string::npos);
  const fs::path bad_seed = work_dir() / "bad_seed.material.json";
  {
    std::string t = text;
    t.replace(t.find("\"seed\": 10000"), 13, "\"seed\": 1.5");
    std::ofstream(bad_seed) << t;
  }
  expect_refused("tunnel", example("tunnel_2d.prm"),
                 "--set \"DEM region/material file=" + bad_seed.string() + "\"",
                 {bad_seed.string(), "'seed'", "integer"});

  const fs::path bad_e = work_dir() / "bad_e.json";
  std::ofstream(bad_e) << "{\"E\": \"3.5e9x\", \"nu\": 0.2}\n";
  expect_refused("fem", example("kirsch_2d.prm"),
                 "--set \"Continuum/material file=" + bad_e.string() + "\"",
                 {bad_e.string(), "'E'"});
}
