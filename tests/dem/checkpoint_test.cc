// HDF5 checkpoints (dem/io/checkpoint.h): a restarted run continues bit for bit,
// writes are atomic and keep the previous file (docs/architecture.md, "Checkpoints and restart"), and a restart
// with different contact-law parameters is refused.
#include "dem/io/checkpoint.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/engine/model.h"

#include <catch2/catch.hpp>
#include <omp.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

using namespace demfem::dem;
namespace fs = std::filesystem;

namespace
{
  struct Threads
  {
    int old = omp_get_max_threads();
    explicit Threads(int n) { omp_set_num_threads(n); }
    ~Threads() { omp_set_num_threads(old); }
  };

  /// A fresh directory for one test case, removed afterwards.
  struct TempDir
  {
    fs::path path;
    explicit TempDir(const std::string &name)
        : path(fs::temp_directory_path() /
               ("demfem_ckpt_" + name + "_" + std::to_string(::getpid())))
    {
      fs::remove_all(path);
      fs::create_directories(path);
    }
    ~TempDir()
    {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
    std::string operator/(const std::string &f) const { return (path / f).string(); }
  };

  double uniform(std::mt19937_64 &g, double a, double b)
  {
    return a + (b - a) * (static_cast<double>(g() >> 11) * 0x1.0p-53);
  }

  /// Bonded flat-joint assembly on a jittered lattice (2D: 20 x 10 disks,
  /// 3D: 5 x 5 x 4 spheres): flat joints on all touching pairs, bottom layer
  /// fixed, top layer moving down, a side wall moving in, linear contacts for
  /// new ball-ball and ball-wall pairs. Same seed, same model.
  template <int dim>
  void build(Model<dim> &m, double fj_ten)
  {
    std::mt19937_64 gen(4242);
    const int       nx = dim == 2 ? 20 : 5, ny = dim == 2 ? 10 : 5, nz = dim == 2 ? 1 : 4;
    const int       nup = dim == 2 ? ny : nz; // layers along the loading axis
    std::vector<int> layer;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          {
            Vec<dim> x;
            x[0] = 2.0 * i, x[1] = 2.0 * j;
            if constexpr (dim == 3)
              x[2] = 2.0 * k;
            for (int d = 0; d < dim; ++d)
              x[d] += uniform(gen, -0.05, 0.05);
            m.particles.add(x, uniform(gen, 0.95, 1.05), 2650);
            layer.push_back(dim == 2 ? j : k);
          }
    typename FlatJointLaw<dim>::Params p;
    p.Nr = dim == 2 ? 3 : 2, p.Nal = 4, p.kn = 1e8, p.ks = 5e7, p.fric = 0.5;
    p.ten = fj_ten, p.coh = 2 * fj_ten, p.fa = 30, p.bonded = true;
    const int                       gfj = m.template add_law<FlatJointLaw<dim>>(p);
    typename LinearLaw<dim>::Params lp;
    lp.kn = dim == 2 ? 1e8 : 1e8, lp.ks = 5e7, lp.friction = 0.5;
    const int glin = m.template add_law<LinearLaw<dim>>(lp);
    m.set_default_law(glin, glin);
    for (std::uint32_t a = 0; a < m.particles.size(); ++a)
      for (std::uint32_t b = a + 1; b < m.particles.size(); ++b)
        if ((m.particles.x[b] - m.particles.x[a]).norm() <
            m.particles.radius[a] + m.particles.radius[b] + 0.1)
          m.install(a, b, gfj);
    for (std::size_t i = 0; i < m.particles.size(); ++i)
      if (layer[i] == 0)
        m.particles.fixity[i] = fix_all;
      else if (layer[i] == nup - 1)
        {
          m.particles.fixity[i]     = fix_translation;
          m.particles.v[i][dim - 1] = -0.5;
        }
    // Side wall at x = -1.1 moving in at 0.2 (ball-wall contacts appear).
    const int w = m.walls.add_wall("side");
    if constexpr (dim == 2)
      {
        const int a = m.walls.add_vertex(Vec<2>(-1.1, -2)),
                  b = m.walls.add_vertex(Vec<2>(-1.1, 20));
        m.walls.add_facet(w, {a, b});
      }
    else
      {
        const int a = m.walls.add_vertex(Vec<3>(-1.1, -2, -2));
        const int b = m.walls.add_vertex(Vec<3>(-1.1, 12, -2));
        const int c = m.walls.add_vertex(Vec<3>(-1.1, 12, 10));
        const int d = m.walls.add_vertex(Vec<3>(-1.1, -2, 10));
        m.walls.add_facet(w, {a, b, c});
        m.walls.add_facet(w, {a, c, d});
      }
    Vec<dim> vw = Vec<dim>::Zero();
    vw[0]       = 0.2;
    m.walls.set_wall_velocity(w, vw);
    m.set_timestep(0); // automatic: the time step changes with the contacts
  }

  template <int dim>
  bool same_cracks(const std::vector<CrackRecord<dim>> &a,
                   const std::vector<CrackRecord<dim>> &b)
  {
    if (a.size() != b.size())
      return false;
    for (std::size_t k = 0; k < a.size(); ++k)
      if (a[k].id1 != b[k].id1 || a[k].id2 != b[k].id2 || a[k].element != b[k].element ||
          a[k].mode != b[k].mode || a[k].position != b[k].position ||
          a[k].normal != b[k].normal || a[k].size != b[k].size || a[k].gap != b[k].gap ||
          a[k].strength != b[k].strength || a[k].step != b[k].step ||
          a[k].time != b[k].time)
        return false;
    return true;
  }

  /// Number of coordinates (positions, velocities, spins) that differ bitwise.
  template <int dim>
  std::size_t differing(const Particles<dim> &a, const Particles<dim> &b)
  {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      {
        for (int d = 0; d < dim; ++d)
          n += (a.x[i][d] != b.x[i][d]) + (a.v[i][d] != b.v[i][d]);
        for (int d = 0; d < rot_dim<dim>; ++d)
          n += a.w[i][d] != b.w[i][d];
      }
    return n;
  }

  template <int dim>
  void restart_bitwise(double fj_ten)
  {
    Threads                                  one(1);
    TempDir                                  dir("restart" + std::to_string(dim));
    const std::string                        file = dir / "model.h5";
    const std::map<std::string, std::string> md   = {
          {"prm", "subsection DEM\n  set seed = 4242\nend\n"}, {"Section/sub/key", "1.5"}};

    Model<dim> a;
    build(a, fj_ten);
    a.cycle(100);
    const std::size_t cracks_at_100   = a.cracks.size();
    const auto        x_at_100        = a.particles.x;
    const std::size_t contacts_at_100 = a.n_contacts();
    write_checkpoint(a, file, md);
    a.cycle(100);

    Model<dim> b;
    build(b, fj_ten);
    std::map<std::string, std::string> md_read;
    read_checkpoint(b, file, &md_read);
    CHECK(md_read == md);
    REQUIRE(b.step_count() == 100);
    CHECK(b.n_contacts() == contacts_at_100);
    b.cycle(100);

    // Not vacuous: the run goes on after the checkpoint (particles move,
    // bonds break, contacts change), so a lost state variable would show.
    double moved = 0;
    for (std::size_t i = 0; i < a.particles.size(); ++i)
      moved = std::max(moved, (a.particles.x[i] - x_at_100[i]).norm());
    CHECK(moved > 1e-3);
    CHECK(a.cracks.size() > cracks_at_100);
    // Bitwise: A == B exactly.
    CHECK(differing(a.particles, b.particles) == 0);
    CHECK(same_cracks(a.cracks, b.cracks));
    CHECK(a.step_count() == b.step_count());
    CHECK(a.time() == b.time());
    CHECK(a.timestep() == b.timestep());
    CHECK(a.n_contacts() == b.n_contacts());
    CHECK(a.walls.vertex == b.walls.vertex);
    for (int g = 0; g < a.n_groups(); ++g)
      CHECK(a.group(g).state_data() == b.group(g).state_data());
    CHECK(a.strain_energy() == b.strain_energy());
    WARN(dim << "D restart: " << a.particles.size() << " particles, contacts "
             << contacts_at_100 << " -> " << a.n_contacts() << ", cracks "
             << cracks_at_100 << " -> " << a.cracks.size()
             << ", max move after the checkpoint " << moved << ", differing coordinates "
             << differing(a.particles, b.particles));
  }

  std::string slurp(const std::string &f)
  {
    std::ifstream     in(f, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
} // namespace

TEST_CASE("checkpoint restart continues bit for bit (2D, 200 disks)", "[checkpoint]")
{
  restart_bitwise<2>(2e5);
}

TEST_CASE("checkpoint restart continues bit for bit (3D, 100 spheres)", "[checkpoint]")
{
  restart_bitwise<3>(2e5);
}

TEST_CASE("checkpoint writes keep the previous file, and a failed write changes nothing",
          "[checkpoint]")
{
  Threads           one(1);
  TempDir           dir("atomic");
  const std::string file = dir / "ck.h5";
  Model<2>          m;
  build(m, 2e5);
  m.cycle(20);
  write_checkpoint(m, file, {{"stage", "first"}});
  CHECK(!fs::exists(file + ".prev")); // nothing to keep yet
  m.cycle(30);
  write_checkpoint(m, file, {{"stage", "second"}});
  CHECK(!fs::exists(file + ".tmp"));
  REQUIRE(fs::exists(file + ".prev"));
  {
    Model<2> r;
    build(r, 2e5);
    std::map<std::string, std::string> md;
    read_checkpoint(r, file + ".prev", &md);
    CHECK(md.at("stage") == "first");
    CHECK(r.step_count() == 20);
    read_checkpoint(r, file, &md);
    CHECK(md.at("stage") == "second");
    CHECK(r.step_count() == 50);
    CHECK(differing(r.particles, m.particles) == 0);
  }
  // A write that cannot create its temporary file (here: a directory is in
  // the way, which stops root too) throws and leaves both files untouched.
  const std::string before = slurp(file), before_prev = slurp(file + ".prev");
  fs::create_directory(file + ".tmp");
  m.cycle(10);
  CHECK_THROWS_AS(write_checkpoint(m, file, {{"stage", "third"}}), std::runtime_error);
  CHECK(slurp(file) == before);
  CHECK(slurp(file + ".prev") == before_prev);
  CHECK(read_checkpoint_metadata(file).at("stage") == "second");
  // Same for a directory that does not exist.
  CHECK_THROWS_AS(write_checkpoint(m, dir / "missing/ck.h5", {}), std::runtime_error);
  CHECK(!fs::exists(dir / "missing"));
  // A non-writable directory (only meaningful when not running as root).
  if (::geteuid() != 0)
    {
      const fs::path ro = dir.path / "ro";
      fs::create_directory(ro);
      fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
      CHECK_THROWS_AS(write_checkpoint(m, (ro / "ck.h5").string(), {}),
                      std::runtime_error);
      fs::permissions(ro, fs::perms::owner_all);
    }
}

TEST_CASE("restart with other contact-law parameters is refused", "[checkpoint]")
{
  Threads           one(1);
  TempDir           dir("params");
  const std::string file = dir / "ck.h5";
  Model<2>          m;
  build(m, 2e5);
  m.cycle(10);
  write_checkpoint(m, file, {});

  Model<2> other; // flat-joint tensile strength differs
  build(other, 3e5);
  const auto x_before = other.particles.x;
  CHECK_THROWS_AS(read_checkpoint(other, file, nullptr), InputError);
  CHECK_THROWS_WITH(
      read_checkpoint(other, file, nullptr),
      Catch::Contains("restart: parameters of contact group 0 (flatjoint) differ "
                      "from the checkpoint") &&
          Catch::Contains("fj_ten is 300000 here, 200000 in the checkpoint"));
  // refused before anything was changed
  CHECK(other.step_count() == 0);
  CHECK(other.particles.x == x_before);

  Model<2> fewer; // one law group missing
  fewer.particles = m.particles;
  fewer.add_law<LinearLaw<2>>(LinearLaw<2>::Params{});
  CHECK_THROWS_WITH(read_checkpoint(fewer, file, nullptr),
                    Catch::Contains("restart: the model has 1 contact groups") &&
                        Catch::Contains("has 2"));

  Model<3> wrong_dim;
  build(wrong_dim, 2e5);
  CHECK_THROWS_WITH(read_checkpoint(wrong_dim, file, nullptr),
                    Catch::Contains("2D model"));
  CHECK_THROWS_AS(read_checkpoint(m, dir / "none.h5", nullptr), InputError);

  // A damaged (truncated) file is bad input and changes nothing.
  const std::string data = slurp(file);
  std::ofstream(dir / "cut.h5", std::ios::binary).write(data.data(), data.size() / 2);
  Model<2> fresh;
  build(fresh, 2e5);
  CHECK_THROWS_AS(read_checkpoint(fresh, dir / "cut.h5", nullptr), InputError);
  CHECK(fresh.step_count() == 0);
  CHECK(fresh.particles.x == x_before);
}
