// A run owns its output directory (docs/tunnel.md, "Output directory: lock,
// manifest, --overwrite"): manifest.json records the run; a second run into a
// directory locked by a live process is refused naming the holder, a stale
// lock is taken over; a used directory is refused unless --overwrite, which
// deletes the old results (and only those). Checked with `demfem fem`, the
// fastest command; tunnel and study share the code (apps/output_dir.cc).
#include "run_command.h"

#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using demfem::testing::run_demfem;

namespace
{
  fs::path fresh_dir(const std::string &name)
  {
    const fs::path d = fs::temp_directory_path() /
                       ("demfem_output_dir_" + name + "_" + std::to_string(getpid()));
    fs::remove_all(d);
    return d;
  }

  std::string read(const fs::path &f)
  {
    std::ifstream     in(f);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  /// The small Kirsch example into `out` (about a second).
  demfem::testing::CommandResult fem(const fs::path &out, const std::string &extra = "")
  {
    return run_demfem("fem " + std::string(DEMFEM_SOURCE_DIR) +
                      "/apps/examples/kirsch_2d.prm --set \"Problem/output directory=" +
                      out.string() + "\" --set \"Continuum/element degree=1\" " + extra);
  }

  std::string host()
  {
    char buf[256] = {};
    gethostname(buf, sizeof buf - 1);
    return buf;
  }

  void write_lock(const fs::path &dir, long pid)
  {
    fs::create_directories(dir);
    std::ofstream(dir / "demfem.lock")
        << "{\"pid\": " << pid << ", \"host\": \"" << host()
        << "\", \"start_time\": \"2026-01-01T00:00:00Z\", \"command_line\": \"demfem "
           "fem other.prm\"}\n";
  }
} // namespace

TEST_CASE("output directory: manifest.json records the run", "[apps][output]")
{
  const fs::path out = fresh_dir("manifest");
  const auto     r   = fem(out);
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  const std::string m = read(out / "manifest.json");
  INFO(m);
  CHECK_THAT(m, Catch::Contains("\"status\": \"ok\""));
  CHECK_THAT(m, Catch::Contains("\"exit_code\": 0"));
  CHECK_THAT(m, Catch::Contains("\"command\": \"fem\""));
  CHECK_THAT(m, Catch::Contains("Continuum/element degree=1")); // the command line
  CHECK_THAT(m, Catch::Contains("\"demfem_version\""));
  CHECK_THAT(m, Catch::Contains("\"start_time\": \"20"));
  CHECK_THAT(m, Catch::Contains("\"end_time\": \"20"));
  CHECK_THAT(m, Catch::Contains("\"parameters\""));
  CHECK_THAT(m, Catch::Contains("\"element degree\"")); // resolved parameters
  CHECK_FALSE(fs::exists(out / "demfem.lock"));         // released at the end
  fs::remove_all(out);
}

TEST_CASE("output directory: a re-run is refused unless --overwrite", "[apps][output]")
{
  const fs::path out = fresh_dir("rerun");
  REQUIRE(fem(out).exit_code == 0);
  const std::string summary = read(out / "summary.json");

  const auto again = fem(out);
  INFO(again.out);
  CHECK(again.exit_code == 1);
  CHECK_THAT(again.out, Catch::Contains("--overwrite") && Catch::Contains(out.string()));
  CHECK(read(out / "summary.json") == summary); // the earlier results are untouched

  // --overwrite deletes the old results (also stale frames the new run would
  // not write), keeps the user's own files, and runs.
  std::ofstream(out / "solution_0099.vtu") << "old frame\n";
  std::ofstream(out / "notes.txt") << "mine\n";
  const auto over = fem(out, "--overwrite");
  INFO(over.out);
  CHECK(over.exit_code == 0);
  CHECK_FALSE(fs::exists(out / "solution_0099.vtu"));
  CHECK(fs::exists(out / "notes.txt"));
  CHECK(fs::exists(out / "summary.json"));
  CHECK_THAT(read(out / "manifest.json"), Catch::Contains("\"overwrite\": true"));
  fs::remove_all(out);
}

TEST_CASE("output directory: a live lock refuses the run, a stale one is taken over",
          "[apps][output]")
{
  const fs::path out = fresh_dir("lock");
  write_lock(out, long(getpid())); // this test process: alive
  const auto busy = fem(out);
  INFO(busy.out);
  CHECK(busy.exit_code == 1);
  CHECK_THAT(busy.out, Catch::Contains("in use by another demfem run") &&
                           Catch::Contains("pid " + std::to_string(getpid())) &&
                           Catch::Contains(host()) &&
                           Catch::Contains("2026-01-01T00:00:00Z"));
  CHECK(fs::exists(out / "demfem.lock")); // not ours to remove
  CHECK_FALSE(fs::exists(out / "summary.json"));

  // A process that has exited: its lock is stale.
  const pid_t child = fork();
  if (child == 0)
    _exit(0);
  REQUIRE(child > 0);
  waitpid(child, nullptr, 0);
  write_lock(out, long(child));
  const auto stale = fem(out);
  INFO(stale.out);
  CHECK(stale.exit_code == 0);
  CHECK_THAT(stale.out, Catch::Contains("stale lock"));
  CHECK(fs::exists(out / "summary.json"));
  CHECK_FALSE(fs::exists(out / "demfem.lock"));
  fs::remove_all(out);
}

TEST_CASE("output directory: the study owns its directory too", "[apps][output][study]")
{
  const fs::path    out = fresh_dir("study");
  const std::string args =
      "study " + std::string(DEMFEM_SOURCE_DIR) +
      "/apps/examples/study_2d.prm --set \"Problem/output directory=" + out.string() +
      "\" --set \"Study/region radius factors=2.5\" --set "
      "\"Study/grain resolutions=3\" --set \"Study/subcycles=1\" "
      "--set \"Study/timestep safety factors=0.8\" --set \"Study/schemes=explicit\"";
  const auto r = run_demfem(args);
  INFO(r.out);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(read(out / "manifest.json"), Catch::Contains("\"status\": \"ok\"") &&
                                              Catch::Contains("\"command\": \"study\""));
  CHECK(fs::exists(out / "summary.json"));
  CHECK(fs::is_directory(out / "run_000"));
  CHECK_FALSE(fs::exists(out / "summary.json.tmp"));

  const auto again = run_demfem(args);
  INFO(again.out);
  CHECK(again.exit_code == 1);
  CHECK_THAT(again.out, Catch::Contains("--overwrite"));

  // --overwrite removes the earlier sub-runs too.
  fs::create_directories(out / "run_007");
  const auto over = run_demfem(args + " --overwrite");
  INFO(over.out);
  CHECK(over.exit_code == 0);
  CHECK_FALSE(fs::exists(out / "run_007"));
  CHECK(fs::is_directory(out / "run_000"));
  fs::remove_all(out);
}
