// Named state of the objects around a model in a checkpoint
// (dem/io/state_archive.h, dem/io/checkpoint.h format version 5): one
// serialize function for saving and loading, round trip bit for bit through
// the HDF5 file, and a missing or misshaped entry refused naming it.
#include "dem/engine/model.h"
#include "dem/io/checkpoint.h"
#include "dem/io/state_archive.h"
#include "dem/laws/linear_law.h"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <filesystem>

using namespace demfem::dem;

namespace
{
  // An object with every kind of entry, as a coupling or workflow has.
  struct Workflow
  {
    double              load_factor = 0;
    int                 phase       = 0;
    std::int64_t        steps       = 0;
    std::size_t         cracks      = 0;
    bool                excavated   = false;
    Vec<2>              force       = Vec<2>::Zero();
    Eigen::Matrix2d     stress      = Eigen::Matrix2d::Zero();
    std::vector<double> history;
    std::vector<Vec<2>> positions;
    void                serialize(StateArchive &ar)
    {
      ar.io("run.load_factor", load_factor);
      ar.io("run.phase", phase);
      ar.io("run.steps", steps);
      ar.io("run.cracks", cracks);
      ar.io("run.excavated", excavated);
      ar.io("run.force", force);
      ar.io("run.stress", stress);
      ar.io("run.history", history);
      ar.io("run.positions", positions, positions.size());
    }
  };

  Workflow sample()
  {
    Workflow w;
    w.load_factor = 1.0 / 3.0;
    w.phase       = -2;
    w.steps       = 9007199254740991; // 2^53 - 1: still exact
    w.cracks      = 1234;
    w.excavated   = true;
    w.force << 1e-300, -7.5e12;
    w.stress << -30e6, 1.0 / 7.0, 2.5, -60e6;
    w.history   = {0.1, 0.2, 0.3};
    w.positions = {Vec<2>(1, 2), Vec<2>(-3.25, 1e-17)};
    return w;
  }
} // namespace

TEST_CASE("state archive: round trip through a checkpoint, bit for bit", "[checkpoint]")
{
  const auto file = std::filesystem::temp_directory_path() /
                    ("demfem_state_archive_" + std::to_string(getpid()) + ".h5");
  Model<2> m;
  for (int i = 0; i < 4; ++i)
    m.particles.add(Vec<2>(2.0 * i, 0.0), 1.0, 2650);
  LinearLaw<2>::Params lp;
  lp.kn = 1e8, lp.ks = 5e7;
  const int g = m.add_law<LinearLaw<2>>(lp);
  m.set_default_law(g, g);
  m.set_timestep(1e-5);
  m.cycle(3);

  Workflow    saved = sample();
  NamedArrays out;
  auto        ar = StateArchive::saving(out);
  saved.serialize(ar);
  write_checkpoint(m, file.string(), {{"prm", "x"}}, out);
  verify_checkpoint(file.string()); // the /state datasets carry checksums too

  NamedArrays                        in;
  std::map<std::string, std::string> md;
  read_checkpoint(m, file.string(), &md, &in);
  CHECK(in == out); // every value, exactly
  Workflow loaded;
  loaded.positions.resize(2); // the loading object knows its sizes
  auto lr = StateArchive::loading(in, file.string());
  loaded.serialize(lr);
  CHECK(loaded.load_factor == saved.load_factor);
  CHECK(loaded.phase == saved.phase);
  CHECK(loaded.steps == saved.steps);
  CHECK(loaded.cracks == saved.cracks);
  CHECK(loaded.excavated == saved.excavated);
  CHECK(loaded.force == saved.force);
  CHECK(loaded.stress == saved.stress);
  CHECK(loaded.history == saved.history);
  CHECK(loaded.positions == saved.positions);
  std::filesystem::remove(file);
}

TEST_CASE("state archive: a missing or misshaped entry is refused naming it",
          "[checkpoint]")
{
  Workflow    saved = sample();
  NamedArrays good;
  auto        ar = StateArchive::saving(good);
  saved.serialize(ar);
  auto expect = [&](NamedArrays arrays, const std::string &what) {
    Workflow w;
    w.positions.resize(2);
    auto lr = StateArchive::loading(arrays, "ck.h5");
    CHECK_THROWS_WITH(w.serialize(lr),
                      Catch::Contains("checkpoint ck.h5") && Catch::Contains(what));
  };
  {
    auto a = good;
    a.erase("run.stress");
    expect(a, "'run.stress' is missing");
  }
  {
    auto a = good;
    a["run.positions"].push_back(0); // 5 values for 2 grains of 2
    expect(a, "'run.positions' has 5 values, expected 4");
  }
  {
    auto a         = good;
    a["run.phase"] = {2.5};
    expect(a, "'run.phase' is not an integer");
  }
  {
    auto a             = good;
    a["run.excavated"] = {2};
    expect(a, "'run.excavated' is not an integer of its type");
  }
}
