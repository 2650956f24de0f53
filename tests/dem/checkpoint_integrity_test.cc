// Checkpoint integrity (dem/io/checkpoint.h, format version 5): every dataset
// carries a Fletcher32 checksum, so a damaged byte is refused on reading,
// naming the dataset and the file, and the model is left unchanged.
#include "dem/io/checkpoint.h"
#include "dem/laws/linear_law.h"
#include "dem/engine/model.h"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace demfem::dem;
namespace fs = std::filesystem;

namespace
{
  // A radius no other number of the file shares, to find its bytes.
  constexpr double marker = 0.9876543210123457;

  void build(Model<2> &m)
  {
    for (int i = 0; i < 8; ++i)
      m.particles.add(Vec<2>(2.0 * i, 0.0), i == 5 ? marker : 1.0, 2650);
    LinearLaw<2>::Params lp;
    lp.kn = 1e8, lp.ks = 5e7;
    const int g = m.add_law<LinearLaw<2>>(lp);
    m.set_default_law(g, g);
    m.set_timestep(1e-5);
  }

  std::string slurp(const std::string &f)
  {
    std::ifstream     in(f, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  fs::path temp(const std::string &name)
  {
    const fs::path d =
        fs::temp_directory_path() / ("demfem_ckpt_integrity_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d / name;
  }
} // namespace

TEST_CASE("checkpoint: a flipped byte in a dataset is refused naming it",
          "[checkpoint][integrity]")
{
  const std::string file = temp("ck.h5").string();
  Model<2>          m;
  build(m);
  m.cycle(5);
  write_checkpoint(m, file, {{"prm", "set radius = 1\n"}});
  verify_checkpoint(file); // intact: no complaint
  {
    Model<2> r;
    build(r);
    CHECK_NOTHROW(read_checkpoint(r, file, nullptr));
  }

  // Flip one bit of the marker radius inside /particles.
  std::string bytes = slurp(file);
  char        pattern[sizeof(double)];
  std::memcpy(pattern, &marker, sizeof marker);
  const auto at = bytes.find(std::string(pattern, sizeof pattern));
  REQUIRE(at != std::string::npos);
  REQUIRE(bytes.find(std::string(pattern, sizeof pattern), at + 1) == std::string::npos);
  bytes[at + 3] ^= 0x10;
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;

  CHECK_THROWS_AS(verify_checkpoint(file), InputError);
  CHECK_THROWS_WITH(verify_checkpoint(file), Catch::Contains(file) &&
                                                 Catch::Contains("Fletcher32") &&
                                                 Catch::Contains("radius"));
  Model<2> r;
  build(r);
  const auto x_before = r.particles.x;
  CHECK_THROWS_WITH(read_checkpoint(r, file, nullptr),
                    Catch::Contains(file) && Catch::Contains("Fletcher32"));
  CHECK(r.particles.x == x_before);
  CHECK(r.step_count() == 0);
  fs::remove_all(fs::path(file).parent_path());
}

TEST_CASE("checkpoint: damaged metadata (the .prm text) is refused too",
          "[checkpoint][integrity]")
{
  const std::string file = temp("ck_meta.h5").string();
  Model<2>          m;
  build(m);
  const std::string text = "set a distinctive parameter line = 12345\n";
  write_checkpoint(m, file, {{"prm", text}});
  CHECK(read_checkpoint_metadata(file).at("prm") == text);
  std::string bytes = slurp(file);
  const auto  at    = bytes.find("distinctive");
  REQUIRE(at != std::string::npos);
  bytes[at] = 'D';
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  CHECK_THROWS_WITH(read_checkpoint_metadata(file),
                    Catch::Contains(file) && Catch::Contains("Fletcher32") &&
                        Catch::Contains("metadata/values"));
  fs::remove_all(fs::path(file).parent_path());
}
