// Smooth-jointed interface inserted into a bonded material (fistPkg §2.8).
#include "dem/laws/flat_joint_law.h"
#include "dem/specimen/joint_insertion.h"
#include "dem/laws/linear_law.h"

#include <catch2/catch.hpp>

using namespace demfem::dem;

namespace
{
  /// 8 x 8 square lattice of touching disks (r = 0.5), flat joints on every
  /// touching pair, linear law for new contacts.
  void bonded_lattice(Model<2> &m, int &fj)
  {
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j)
        m.particles.add(Vec<2>(i * 1.0, j * 1.0), 0.5, 2650);
    LinearLaw<2>::Params lp;
    lp.kn = 1e8, lp.ks = 1e8, lp.friction = 0.5;
    m.set_default_law(m.add_law<LinearLaw<2>>(lp), -1);
    m.skin = 0.05;
    m.detect_contacts();
    FlatJointLaw<2>::Params fp;
    fp.Nr = 2, fp.kn = 1e11, fp.ks = 5e10, fp.ten = 1e12, fp.coh = 1e12, fp.bonded = true;
    fj = m.add_law<FlatJointLaw<2>>(fp);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::size_t k = 0; k < m.group(0).size(); ++k)
      pairs.emplace_back(m.group(0).end1[k], m.group(0).end2[k]);
    for (auto [i, j] : pairs)
      m.install(i, j, fj);
  }
} // namespace

TEST_CASE("smooth joint replaces exactly the contacts across the plane", "[joint]")
{
  Model<2> m;
  int      fj = -1;
  bonded_lattice(m, fj);
  REQUIRE(m.group(fj).size() == 2 * 8 * 7); // 56 horizontal + 56 vertical pairs

  JointPlane<2> plane;
  plane.point = Vec<2>(0, 3.5); // between rows 3 and 4
  plane.sj.sj_kn = 1e11, plane.sj.sj_ks = 5e10, plane.sj.sj_fric = 0.0;
  plane.sj.dip = 0; // seed 001 Eq. 1: n_j = (sin 0, cos 0) = +y
  int        sj = -1;
  const auto n  = insert_smooth_joint(m, plane, sj);
  CHECK(n == 8); // the 8 vertical pairs crossing y = 3.5
  CHECK(m.group(sj).size() == 8);
  CHECK(m.group(fj).size() == 2 * 8 * 7 - 8);
  CHECK(std::string(m.group(sj).law_name()) == "smoothjoint");
  for (std::size_t k = 0; k < m.group(sj).size(); ++k)
    CHECK(plane.crosses(m.particles.x[m.group(sj).end1[k]], m.particles.x[m.group(sj).end2[k]]));

  // A new contact across the plane gets the smooth joint; one beside it the
  // default linear law.
  m.particles.add(Vec<2>(9.0, 3.0), 0.5, 2650);
  m.particles.add(Vec<2>(9.0, 3.99), 0.5, 2650); // overlapping, across y = 3.5
  m.particles.add(Vec<2>(11.0, 1.0), 0.5, 2650);
  m.particles.add(Vec<2>(11.0, 1.99), 0.5, 2650); // overlapping, below the plane
  m.invalidate_contacts();
  m.detect_contacts();
  CHECK(m.find(64, 65).group == sj);
  CHECK(m.find(66, 67).group == 0);
}

TEST_CASE("a frictionless joint lets the upper block slide", "[joint]")
{
  // Shear the lattice: bottom row fixed, top row pushed along +x. Without the
  // joint the bonded block shears elastically; with a frictionless joint the
  // upper half slides as a block on it: the relative displacement across the
  // joint carries nearly all of the top-row motion.
  auto run = [](bool joint) {
    Model<2> m;
    int      fj = -1;
    bonded_lattice(m, fj);
    if (joint)
      {
        JointPlane<2> plane;
        plane.point    = Vec<2>(0, 3.5);
        plane.sj.sj_kn = 1e11, plane.sj.sj_ks = 5e10, plane.sj.sj_fric = 0.0;
        int sj         = -1;
        insert_smooth_joint(m, plane, sj);
      }
    for (std::size_t i = 0; i < m.particles.size(); ++i)
      {
        if (m.particles.x[i][1] < 0.1)
          m.particles.fixity[i] = fix_all;
        if (m.particles.x[i][1] > 6.9)
          {
            m.particles.fixity[i] = fix_all;
            m.particles.v[i]      = Vec<2>(1e-2, 0);
          }
      }
    m.set_timestep(0);
    m.cycle(3000);
    // Mean x displacement of row 4 (just above the joint) and row 3 (below).
    double above = 0, below = 0;
    for (std::size_t i = 0; i < m.particles.size(); ++i)
      {
        const double y0 = m.particles.x0[i][1], dx = m.particles.x[i][0] - m.particles.x0[i][0];
        if (std::abs(y0 - 4) < 0.1)
          above += dx / 8;
        if (std::abs(y0 - 3) < 0.1)
          below += dx / 8;
      }
    const double top = m.particles.x[63][0] - m.particles.x0[63][0];
    return std::tuple{above, below, top};
  };
  const auto [a0, b0, t0] = run(false);
  const auto [a1, b1, t1] = run(true);
  REQUIRE(t0 > 0);
  WARN("jump across the middle gap / top displacement: intact " << (a0 - b0) / t0
                                                               << ", jointed " << (a1 - b1) / t1);
  // Intact block: shear strain spread over 7 row gaps, jump across the
  // middle gap about 1/7 of the top displacement (elastic, < 0.3 allowed).
  CHECK((a0 - b0) / t0 < 0.3);
  // Jointed block: the jump across the joint carries most of the motion.
  CHECK((a1 - b1) / t1 > 0.8);
}
