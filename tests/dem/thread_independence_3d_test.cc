// 3D counterpart of "results do not depend on the thread count": a bonded
// sphere assembly under compression exercises the blocked contact loop (16
// contacts per block, blocks shared among threads), the 3D flat-joint fast
// path and, once elements break, the general loop. One and two threads must
// give the same bits.
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/engine/model.h"

#include <catch2/catch.hpp>
#include <omp.h>

#include <random>
#include <vector>

using namespace demfem::dem;

namespace
{
  struct Run
  {
    std::vector<Vec<3>> x, w;
    std::size_t         cracks = 0, contacts = 0;
  };

  Run compress(int threads)
  {
    const int         old_threads = omp_get_max_threads();
    const std::size_t old_limit   = parallel_threshold;
    omp_set_num_threads(threads);
    parallel_threshold = 0; // threaded loops even for this small model

    Model<3>        m;
    std::mt19937_64 gen(7);
    auto            u = [&](double a, double b) {
      return a + (b - a) * double(gen() >> 11) * 0x1.0p-53;
    };
    const int n = 5; // 5 x 5 x 5 simple cubic lattice, spacing 2
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          m.particles.add(Vec<3>(2.0 * i + u(-0.03, 0.03), 2.0 * j + u(-0.03, 0.03),
                                 2.0 * k + u(-0.03, 0.03)),
                          u(0.97, 1.03), 2650);
    FlatJointLaw<3>::Params p;
    p.Nr = 2, p.Nal = 8, p.kn = 1e8, p.ks = 5e7, p.fric = 0.5;
    p.ten = 1e4, p.coh = 2e4, p.fa = 30, p.bonded = true;
    const int            gfj = m.add_law<FlatJointLaw<3>>(p);
    LinearLaw<3>::Params lp;
    lp.kn = 1e8, lp.ks = 5e7, lp.friction = 0.5;
    m.set_default_law(m.add_law<LinearLaw<3>>(lp), -1);
    for (std::uint32_t a = 0; a < m.particles.size(); ++a)
      for (std::uint32_t b = a + 1; b < m.particles.size(); ++b)
        if ((m.particles.x[b] - m.particles.x[a]).norm() <
            m.particles.radius[a] + m.particles.radius[b] + 0.1)
          m.install(a, b, gfj);
    for (std::size_t i = 0; i < m.particles.size(); ++i)
      {
        const double z = m.particles.x[i][2];
        if (z < 0.5) // bottom layer fixed
          m.particles.fixity[i] = fix_all;
        else if (z > 2.0 * (n - 1) - 0.5) // top layer pushed down and sideways
          {
            m.particles.fixity[i] = fix_all;
            m.particles.v[i]      = Vec<3>(0.05, 0.0, -0.5);
          }
      }
    m.set_timestep(0);
    m.cycle(300);
    Run r{m.particles.x, m.particles.w, m.cracks.size(), m.n_contacts()};
    omp_set_num_threads(old_threads);
    parallel_threshold = old_limit;
    return r;
  }
} // namespace

TEST_CASE("3D: results do not depend on the thread count", "[enginelaws]")
{
  const Run a = compress(1);
  const Run b = compress(2);
  REQUIRE(a.x.size() == 125);
  REQUIRE(a.contacts > 32); // more than two blocks of 16 contacts
  std::size_t identical = 0;
  double      moved     = 0;
  for (std::size_t i = 0; i < a.x.size(); ++i)
    for (int d = 0; d < 3; ++d)
      identical += (a.x[i][d] == b.x[i][d]) + (a.w[i][d] == b.w[i][d]);
  for (std::size_t i = 25; i < 100; ++i) // free layers moved (not vacuous)
    moved = std::max(moved, std::abs(a.x[i][2] - 2.0 * double(i / 25)));
  CHECK(moved > 0.1); // jitter is 0.03
  WARN("3D thread independence: contacts " << a.contacts << ", cracks " << a.cracks
                                           << ", max moved " << moved);
  CHECK(a.cracks > 0); // the general loop ran too (breakage)
  CHECK(a.cracks == b.cracks);
  CHECK(identical == 6 * a.x.size()); // every coordinate and spin, bitwise
}
