// The material file read back (dem/specimen/material_file.h): the committed 2D Lac du
// Bonnet material.json gives the microparameters its calibration used, and
// a broken file is refused naming the file and the key.
#include "dem/specimen/material_file.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

using namespace demfem::dem;

namespace
{
  std::string example(const std::string &name)
  {
    return std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/" + name;
  }
} // namespace

TEST_CASE("material file: the 2D Lac du Bonnet microparameters read back", "[material]")
{
  const auto  f = read_material_file(example("lac_du_bonnet_2d.material.json"));
  const auto &p = f.material;
  CHECK(f.dim == 2);
  CHECK(p.type == "flatjointed");
  REQUIRE(p.sizes.size() == 1);
  CHECK_FALSE(p.sizes[0].gaussian);
  CHECK(p.sizes[0].d_lo == 0.001);
  CHECK(p.sizes[0].d_hi == 0.00166);
  CHECK(p.diameter_multiplier == Approx(0.90061944006800432).epsilon(1e-15));
  // apps/examples/lac_du_bonnet_2d.prm, to the digits written there.
  CHECK(p.emod == 107.5e9);
  CHECK(p.krat == Approx(3.7).epsilon(1e-15));
  CHECK(p.lnm_emod == 100e9);
  CHECK(p.igap == Approx(60e-6).epsilon(1e-15));
  CHECK(p.fj_ten.mean == 23.5e6);
  CHECK(p.fj_ten.sd == 9.6e6);
  CHECK(p.fj_ten.min == 10e6);
  CHECK(p.fj_coh.mean == 370e6);
  CHECK(p.fj_fa == 20);
  CHECK(p.fj_B == Approx(0.925).epsilon(1e-15));
  CHECK(p.fj_G == 0);
  CHECK(p.fj_Nr == 2);
  CHECK(p.Pm == 1e6);
  CHECK(p.seed == 10000);
}

TEST_CASE("material file: a broken file is refused naming the file and the key",
          "[material]")
{
  const auto dir = std::filesystem::temp_directory_path() / "demfem_material_file_test";
  std::filesystem::create_directories(dir);
  const std::string good = example("lac_du_bonnet_2d.material.json");
  std::ifstream     in(good);
  REQUIRE(in);
  std::string text((std::istreambuf_iterator<char>(in)),
                   std::istreambuf_iterator<char>());

  // Missing key: emod_Pa removed.
  {
    std::string t   = text;
    const auto  pos = t.find("\"emod_Pa\"");
    REQUIRE(pos != std::string::npos);
    t.replace(pos, 9, "\"emod_Xx\"");
    const auto f = (dir / "missing.json").string();
    std::ofstream(f) << t;
    CHECK_THROWS_WITH(read_material_file(f),
                      Catch::Contains("emod_Pa") && Catch::Contains("missing.json"));
  }
  // Out of range: a negative stiffness is caught by the material's own
  // validation, which names the key.
  {
    std::string t   = text;
    const auto  pos = t.find("\"emod_Pa\": ");
    REQUIRE(pos != std::string::npos);
    t.insert(pos + 11, "-");
    const auto f = (dir / "negative.json").string();
    std::ofstream(f) << t;
    CHECK_THROWS_AS(read_material_file(f), InputError);
  }
  // Not JSON at all, and no file.
  {
    const auto f = (dir / "garbage.json").string();
    std::ofstream(f) << "{ not json";
    CHECK_THROWS_WITH(read_material_file(f), Catch::Contains("not valid JSON"));
    CHECK_THROWS_WITH(read_material_file((dir / "none.json").string()),
                      Catch::Contains("none.json"));
  }
  std::filesystem::remove_all(dir);
}
