// `demfem fem` with bad input: non-zero exit, a message on stderr that names
// the parameter/file and the allowed range, and nothing written.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace
{
  struct Result
  {
    int         exit_code;
    std::string err;
  };

  fs::path work_dir()
  {
    static const fs::path dir =
        fs::temp_directory_path() / ("demfem_fem_bad_input_" + std::to_string(getpid()));
    fs::create_directories(dir);
    return dir;
  }

  Result run_fem(const std::string &args)
  {
    const fs::path    err_file = work_dir() / "stderr.txt";
    const std::string cmd = std::string("timeout 60 ") + DEMFEM_EXE + " fem " + args +
                            " > /dev/null 2> " + err_file.string();
    const int         status = std::system(cmd.c_str());
    std::ifstream     in(err_file);
    std::stringstream ss;
    ss << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
  }

  std::string example()
  {
    return std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/kirsch_2d.prm";
  }

  // Runs the example with extra arguments into a fresh output directory and
  // checks failure, the message fragments and that nothing was written.
  void expect_failure(const std::string &extra, const std::vector<std::string> &fragments)
  {
    const fs::path out = work_dir() / "out";
    fs::remove_all(out);
    const Result r = run_fem(
        example() + " --set \"Problem/output directory=" + out.string() + "\" " + extra);
    INFO("arguments: " << extra << "\nstderr: " << r.err);
    CHECK(r.exit_code != 0);
    CHECK(r.exit_code != 124); // not a timeout
    for (const auto &f : fragments)
      CHECK(r.err.find(f) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
} // namespace

TEST_CASE("fem: missing mesh file is rejected", "[apps][fem]")
{
  expect_failure("--set \"Continuum/mesh=/nonexistent/tunnel.msh\"",
                 {"Continuum/mesh", "/nonexistent/tunnel.msh"});
}

TEST_CASE("fem: mesh without boundary ids 1 and 3 is rejected", "[apps][fem]")
{
  // One quadrilateral whose boundary lines carry physical tag 7 only.
  const fs::path msh = work_dir() / "no_ids.msh";
  std::ofstream(msh) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n"
                        "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n$Elements\n5\n"
                        "1 1 2 7 1 1 2\n2 1 2 7 1 2 3\n3 1 2 7 1 3 4\n4 1 2 7 1 4 1\n"
                        "5 3 2 0 1 1 2 3 4\n$EndElements\n";
  expect_failure("--set \"Continuum/mesh=" + msh.string() + "\"",
                 {"Continuum/mesh", "no_ids.msh", "id 1"});
}

TEST_CASE("fem: non-positive Young's modulus is rejected", "[apps][fem]")
{
  expect_failure("--set \"Continuum/young modulus=0\"", {"young modulus", "> 0"});
  expect_failure("--set \"Continuum/young modulus=-5e9\"", {"young modulus", "> 0"});
}

TEST_CASE("fem: Poisson's ratio outside (-1, 0.5) is rejected", "[apps][fem]")
{
  expect_failure("--set \"Continuum/poisson ratio=0.5\"", {"poisson ratio", "(-1, 0.5)"});
  expect_failure("--set \"Continuum/poisson ratio=-1\"", {"poisson ratio", "(-1, 0.5)"});
}

TEST_CASE("fem: unknown keys are rejected", "[apps][fem]")
{
  expect_failure("--set \"Continuum/youngs modulus=1e9\"", {"youngs modulus"});
  const fs::path prm = work_dir() / "unknown.prm";
  std::ofstream(prm) << "subsection Continuum\n  set element degre = 2\nend\n";
  const fs::path out = work_dir() / "out";
  fs::remove_all(out);
  const Result r =
      run_fem(prm.string() + " --set \"Problem/output directory=" + out.string() + "\"");
  INFO("stderr: " << r.err);
  CHECK(r.exit_code != 0);
  CHECK(r.err.find("element degre") != std::string::npos);
  CHECK(r.err.find("unknown.prm") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("fem: missing material file is rejected", "[apps][fem]")
{
  expect_failure("--set \"Continuum/material file=/nonexistent/material.json\"",
                 {"Continuum/material file", "/nonexistent/material.json"});
}

TEST_CASE("fem: material file sets E and nu", "[apps][fem]")
{
  const fs::path json = work_dir() / "material.json";
  std::ofstream(json) << "{\"E\": 5e10, \"nu\": 0.2, \"UCS\": 1.5e8}\n";
  const fs::path out = work_dir() / "out_material";
  fs::remove_all(out);
  const Result r =
      run_fem(example() + " --set \"Problem/output directory=" + out.string() +
              "\" --set \"Continuum/material file=" + json.string() +
              "\" --set \"Continuum/element degree=1\"");
  INFO("stderr: " << r.err);
  REQUIRE(r.exit_code == 0);
  std::ifstream     in(out / "summary.json");
  std::stringstream ss;
  ss << in.rdbuf();
  CHECK(ss.str().find("\"E\": 50000000000") != std::string::npos);
  CHECK(ss.str().find("\"nu\": 0.2") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("fem: a mesh body under another version's header is rejected", "[apps][fem]")
{
  // The example's 2.2 mesh with its header changed to 4.1: the reader used
  // to allocate from the misread counts without bound (about 170 MB/s until
  // killed); the section headers are now checked first, and the run stops
  // at once (within the 60 s timeout of run_fem, in practice milliseconds).
  std::ifstream     in(std::string(DEMFEM_SOURCE_DIR) + "/meshes/tunnel_2d.msh");
  std::stringstream body;
  body << in.rdbuf();
  std::string text = body.str();
  REQUIRE(text.find("2.2 0 8") != std::string::npos);
  text.replace(text.find("2.2 0 8"), 7, "4.1 0 8");
  const fs::path msh = work_dir() / "wrong_version.msh";
  std::ofstream(msh) << text;
  expect_failure("--set \"Continuum/mesh=" + msh.string() + "\"",
                 {"Continuum/mesh", "wrong_version.msh", "$Nodes", "version 4.1"});
}
