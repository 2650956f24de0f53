// `demfem tunnel` with 'DEM region/radius = auto' (right-sizing,
// docs/architecture.md, "Speed-versus-accuracy study"): without a UCS the run
// stops before writing anything and names the keys.
#include "run_command.h"

#include <catch2/catch.hpp>

#include <filesystem>

TEST_CASE("tunnel: radius = auto needs a UCS and writes nothing without it", "[tunnel][auto]")
{
  namespace fs   = std::filesystem;
  const auto out = fs::temp_directory_path() / "demfem_tunnel_auto_no_ucs";
  fs::remove_all(out);
  const auto r = demfem::testing::run_demfem(
      std::string("tunnel ") + DEMFEM_SOURCE_DIR + "/apps/examples/tunnel_2d.prm" +
      " --set \"DEM region/material file=\" --set \"DEM region/radius=auto\" --set \"Problem/output directory=" + out.string() +
      "\"");
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.out, Catch::Contains("DEM region/radius = auto") && Catch::Contains("Study/ucs"));
  CHECK(!fs::exists(out));
}
