// Bounded memory (dem/specimen/memory_budget.h): a specimen or region whose estimated
// memory exceeds the limit is refused before anything is allocated or
// written, naming the key that sets the grain size and the limit's key.
#include "run_command.h"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>

namespace fs = std::filesystem;
using demfem::testing::run_demfem;
using demfem::testing::run_with_threads;

namespace
{
  fs::path out_dir(const std::string &name)
  {
    const fs::path d = fs::temp_directory_path() /
                       ("demfem_memory_test_" + std::to_string(getpid())) / name;
    fs::remove_all(d);
    return d;
  }
} // namespace

TEST_CASE("memory budget: tunnel regions and calibrate specimens are bounded", "[memory]")
{
  const std::string ex = std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/";
  SECTION("1 mm grains in the example region (about 4e7 grains)")
  {
    const fs::path out = out_dir("fine");
    const auto     r   = run_demfem("tunnel " + ex + "tunnel_2d.prm" +
                                    " --set \"DEM region/grain diameter=0.001\""
                                          " --set \"Problem/output directory=" +
                                    out.string() + "\"");
    INFO(r.out);
    CHECK(r.exit_code == 1);
    CHECK(r.out.find("DEM region/grain diameter") != std::string::npos);
    CHECK(r.out.find("DEM region/memory limit") != std::string::npos);
    CHECK(!fs::exists(out));
  }
  SECTION("the limit is a key")
  {
    const fs::path out = out_dir("limit");
    const auto     r   = run_demfem("tunnel " + ex + "tunnel_2d.prm" +
                                    " --set \"DEM region/memory limit=0.001\""
                                          " --set \"Problem/output directory=" +
                                    out.string() + "\"");
    CHECK(r.exit_code == 1);
    CHECK(r.out.find("above the memory limit of 0.001 GB") != std::string::npos);
    CHECK(!fs::exists(out));
  }
  SECTION("calibrate: a tiny diameter multiplier")
  {
    const fs::path out = out_dir("calibrate");
    const auto     r   = run_demfem("calibrate " + ex + "lac_du_bonnet_2d.prm" +
                                    " --set \"Material/number of grains=0\""
                                          " --set \"Material/diameter multiplier=0.001\""
                                          " --set \"Problem/output directory=" +
                                    out.string() + "\"");
    CHECK(r.exit_code == 1);
    CHECK(r.out.find("Material/diameter multiplier") != std::string::npos);
    CHECK(r.out.find("Problem/memory limit") != std::string::npos);
    CHECK(!fs::exists(out));
  }
  SECTION("calibrate: packings side by side share the limit")
  {
    // The example's 1 000 grains need about 3.1 MB (3.1 kB a grain in 2D):
    // one packing fits 5 MB, two side by side (two threads) do not.
    const fs::path out = out_dir("side_by_side");
    const auto     r =
        run_with_threads("calibrate " + ex + "lac_du_bonnet_2d.prm" +
                             " --set Problem/seeds=2 --set \"Problem/memory limit=0.005\""
                             " --set \"Problem/output directory=" +
                             out.string() + "\"",
                         2);
    INFO(r.out);
    CHECK(r.exit_code == 1);
    CHECK(r.out.find("2 packings side by side") != std::string::npos);
    CHECK(r.out.find("OMP_NUM_THREADS") != std::string::npos);
    CHECK(!fs::exists(out));
  }
}
