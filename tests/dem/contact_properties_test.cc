// Per-contact property blocks (docs/architecture.md, "Per-contact
// properties"): the deformability rule, strength draws, one group per law,
// the run-time property API, checkpoints, crack types.
#include "dem/io/checkpoint.h"
#include "dem/laws/smooth_joint_law.h"
#include "dem/specimen/genesis.h"
#include "dem/specimen/property_rules.h"

#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <tuple>

using namespace demfem::dem;

namespace
{
  struct Threads
  {
    int old = omp_get_max_threads();
    explicit Threads(int n) { omp_set_num_threads(n); }
    ~Threads() { omp_set_num_threads(old); }
  };

  /// A polydisperse flat-jointed material with a strength spread.
  MaterialParams spread_material()
  {
    MaterialParams p;
    p.type     = "flatjointed";
    p.sizes    = {SizePiece{false, 1.0e-3, 2.0e-3, 0, 0, 1.0}};
    p.lnm_emod = 4e10;
    p.lnm_krat = 1.5;
    p.emod     = 4e10;
    p.krat     = 2.0;
    p.fric     = 0.4;
    p.fj_B     = 0.7;
    p.fj_G     = 0.1;
    p.fj_gap   = {1e-5, 2e-6};
    p.fj_ten   = {1e7, 4e6};
    p.fj_coh   = {4e7, 1e7};
    p.fj_fa    = 30;
    p.Pm       = 1e5;
    return p;
  }

  /// Mean, sd and smallest of n tensile strengths drawn by the flat-joint
  /// rule genesis uses (2D, equal radii).
  std::tuple<double, double, double> sample_tensile_strengths(const Distribution &ten,
                                                              const Distribution &coh,
                                                              std::uint64_t seed, int n)
  {
    auto rule = flat_joint_rule<2>({4e10, 2.0}, ten, coh, StrengthDraws(seed));
    ContactGeometry<2> g;
    g.R1 = g.R2 = 1e-3;
    double s1 = 0, s2 = 0, smin = HUGE_VAL;
    for (int i = 0; i < n; ++i)
      {
        FlatJointLaw<2>::Props q;
        rule(g, q);
        s1 += q.ten;
        s2 += q.ten * q.ten;
        smin = std::min(smin, q.ten);
      }
    const double mean = s1 / n;
    return {mean, std::sqrt(s2 / n - mean * mean), smin};
  }

  VesselParams box(double W, double H)
  {
    VesselParams v;
    v.W = W;
    v.H = H;
    v.D = 1;
    return v;
  }

  const Specimen<2> &specimen()
  {
    static const Specimen<2> s = [] {
      auto p = spread_material();
      set_grain_count<2>(p, box(0.04, 0.04), 200);
      return build_specimen<2>(p, box(0.04, 0.04));
    }();
    return s;
  }
} // namespace

TEST_CASE("per-contact kn is E*/L on a polydisperse packing, one group per law",
          "[properties]")
{
  const auto &s = specimen();
  const auto &m = s.model;
  const auto &P = m.particles;
  // One flat-joint group, one linear group, one grain-wall group (plus the
  // packing groups, now empty of grain pairs).
  int n_fj = 0;
  for (int g = 0; g < m.n_groups(); ++g)
    n_fj += std::string(m.group(g).law_name()) == "flatjoint";
  CHECK(n_fj == 1);
  const auto &fj = s.model.group(s.bond_group);
  REQUIRE(fj.size() > 100);
  double Lmin = HUGE_VAL, Lmax = 0;
  for (std::size_t k = 0; k < fj.size(); ++k)
    {
      const double L = P.radius[fj.end1[k]] + P.radius[fj.end2[k]];
      Lmin           = std::min(Lmin, L);
      Lmax           = std::max(Lmax, L);
      // Memo Eq. 40, evaluated as the rule does: round-off only.
      CHECK(fj.property(k, "fj_kn") == Approx(4e10 / L).epsilon(1e-15));
      CHECK(fj.property(k, "fj_ks") == Approx(2e10 / L).epsilon(1e-15));
    }
  CHECK(Lmax > 1.3 * Lmin); // the check covered a real size range
  // Linear grain-grain contacts: kn = 2 R_min E*/L (2D, force per
  // displacement), per contact.
  const auto &lin = m.group(s.linear_group);
  for (std::size_t k = 0; k < lin.size(); ++k)
    if (!lin.is_wall[k])
      {
        const double r1 = P.radius[lin.end1[k]], r2 = P.radius[lin.end2[k]];
        CHECK(lin.property(k, "kn") ==
              Approx(2 * std::min(r1, r2) * 4e10 / (r1 + r2)).epsilon(1e-15));
      }
  // Grain-wall: L = R1 (memo Eq. 40): kn = 2 R E_w / R.
  const auto &wall = m.group(s.wall_group);
  REQUIRE(wall.size() > 0);
  for (std::size_t k = 0; k < wall.size(); ++k)
    CHECK(wall.property(k, "kn") == Approx(2 * s.vessel.params.emod).epsilon(1e-15));
}

TEST_CASE("strength draws truncated at a point above zero: none below it and the "
          "truncated normal's mean and sd: a point at the mean is refused",
          "[properties]")
{
  // sd / mean = 0.42 (the 2D Lac du Bonnet example's spread) truncated at
  // 0.5 mean: 12 % of the normal lies below the point, so the draws'
  // moments differ from the untruncated ones by far more than the sampling
  // error and must follow the closed form with a = (min - mean) / sd.
  const Distribution ten{30e6, 12.6e6, 15e6}, coh{4e7, 0};
  const int          n        = 20000;
  const auto [mean, sd, smin] = sample_tensile_strengths(ten, coh, 2024, n);
  const double m0 = truncated_normal_mean(ten), sd0 = truncated_normal_sd(ten);
  CHECK(smin > ten.min);
  // The truncation moves the mean by 0.21 sd and the sd by 18 %: 4
  // standard errors (0.028 sd0 and 0.02 sd0) separate the two.
  CHECK(m0 - ten.mean > 0.2 * ten.sd);
  CHECK(std::abs(mean - m0) < 4 * sd0 / std::sqrt(double(n)));
  CHECK(std::abs(sd - sd0) < 4 * sd0 / std::sqrt(2.0 * n));
  // min = 0 is the former truncation at zero, bit for bit.
  CHECK(truncated_normal_mean({1e7, 8e6, 0}) == truncated_normal_mean({1e7, 8e6}));
  // A truncation point at or above the mean is refused, naming the key.
  MaterialParams m = spread_material();
  m.fj_ten         = {30e6, 12.6e6, 30e6};
  CHECK_THROWS_WITH(m.validate("test"), Catch::Contains("fj_ten_min"));
  m.fj_ten = {30e6, 12.6e6, -1e6}; // below zero
  CHECK_THROWS_WITH(m.validate("test"), Catch::Contains("fj_ten_min"));
  m.fj_ten = {30e6, 12.6e6, 29e6};
  CHECK_NOTHROW(m.validate("test"));
}

TEST_CASE("strength draws keep the truncated normal's mean and sd, none is zero",
          "[properties]")
{
  // The rule genesis uses, on 2 x 10^4 contacts. sd / mean = 0.8: the
  // truncation at zero matters (11 % of the normal lies below it), so the
  // draws are compared with the truncated normal's closed-form moments.
  const Distribution ten{1e7, 8e6}, coh{4e7, 1e7};
  const int          n        = 20000;
  const auto [mean, sd, smin] = sample_tensile_strengths(ten, coh, 12345, n);
  const double m0 = truncated_normal_mean(ten), sd0 = truncated_normal_sd(ten);
  // Sampling error of the mean sd0 / sqrt(n) = 0.0071 sd0: 4 standard errors.
  CHECK(std::abs(mean - m0) < 4 * sd0 / std::sqrt(double(n)));
  // Of the sd about sd0 / sqrt(2 n) = 0.005 sd0: 4 standard errors.
  CHECK(std::abs(sd - sd0) < 4 * sd0 / std::sqrt(2.0 * n));
  CHECK(smin > 0);
  // Closed form against the untruncated limit (sd << mean).
  CHECK(truncated_normal_mean({1.0, 1e-3}) == Approx(1.0).epsilon(1e-12));
  CHECK(truncated_normal_sd({1.0, 1e-3}) == Approx(1e-3).epsilon(1e-9));

  // In a genesis specimen every bonded joint has its own draw, none zero.
  const auto         &fj = specimen().model.group(specimen().bond_group);
  std::vector<double> v;
  for (std::size_t k = 0; k < fj.size(); ++k)
    v.push_back(fj.property(k, "fj_ten"));
  std::sort(v.begin(), v.end());
  CHECK(v.front() > 0);
  CHECK(std::unique(v.begin(), v.end()) == v.end()); // no two alike (no binning)
}

TEST_CASE("initial microstructural types and radius multipliers are per contact",
          "[properties]")
{
  const auto &fj   = specimen().model.group(specimen().bond_group);
  std::size_t n[5] = {0, 0, 0, 0, 0};
  for (std::size_t k = 0; k < fj.size(); ++k)
    {
      const int t = static_cast<int>(fj.property(k, "fj_mtype"));
      REQUIRE(t >= 1);
      REQUIRE(t <= 3);
      ++n[t];
      if (t == 2)
        CHECK(fj.property(k, "fj_gap0") > 0);
      else
        CHECK(fj.property(k, "fj_gap0") == 0);
    }
  const double N = fj.size();
  // fistPkg Eq. 1: n_B = round(phi_B N), n_G = round(phi_G N).
  CHECK(n[1] == std::llround(0.7 * N));
  CHECK(n[2] == std::llround(0.1 * N));
  CHECK(n[1] + n[2] + n[3] == fj.size());
}

TEST_CASE("a single-valued group and the per-contact rule give the same run",
          "[properties]")
{
  // Monodisperse chain of bonded flat joints compressed: one group whose
  // Params carry kn = E*/L (the single-valued material before per-contact
  // blocks) and one whose rule sets kn per contact give bitwise the same
  // positions: the per-contact path adds no arithmetic.
  Threads one(1);
  auto    run = [](bool rule) {
    Model<2>     m;
    const double r = 1e-3, E = 4e10;
    for (int i = 0; i < 6; ++i)
      m.particles.add(Vec<2>(2 * r * i, 0), r, 2650);
    FlatJointLaw<2>::Params q;
    q.Nr     = 2;
    q.fric   = 0.5;
    q.fa     = 30;
    q.bonded = true;
    int g;
    if (rule)
      g = m.add_law<FlatJointLaw<2>>(
          q, "rule", flat_joint_rule<2>({E, 2.0}, {5e6, 0}, {2e7, 0}, StrengthDraws(1)));
    else
      {
        q.kn  = E / (2 * r);
        q.ks  = q.kn / 2.0;
        q.ten = 5e6;
        q.coh = 2e7;
        g     = m.add_law<FlatJointLaw<2>>(q, "single");
      }
    for (std::uint32_t i = 0; i + 1 < 6; ++i)
      m.install(i, i + 1, g);
    m.particles.fixity[0] = fix_all;
    m.particles.fixity[5] = fix_all;
    m.particles.v[5][0]   = -0.05;
    m.particles.v[5][1]   = 0.01;
    m.set_timestep(1e-8);
    m.cycle(2000);
    return m.particles.x;
  };
  const auto a = run(true), b = run(false);
  for (std::size_t i = 0; i < a.size(); ++i)
    CHECK(std::memcmp(a[i].data(), b[i].data(), sizeof(double) * 2) == 0);
}

namespace
{
  /// Two grains joined by a bonded flat joint, grain 1 pulled along x.
  struct Pair
  {
    Model<2> m;
    int      g = -1;
    Pair()
    {
      const double r = 1e-3;
      m.particles.add(Vec<2>(0, 0), r, 2650);
      m.particles.add(Vec<2>(2 * r, 0), r, 2650);
      FlatJointLaw<2>::Params q;
      q.Nr     = 2;
      q.fric   = 0.5;
      q.fa     = 30;
      q.bonded = true;
      g        = m.add_law<FlatJointLaw<2>>(
          q, "pair",
          flat_joint_rule<2>({4e10, 2.0}, {1e9, 0}, {1e10, 0}, StrengthDraws(1)));
      m.install(0, 1, g);
      m.particles.fixity[0] = m.particles.fixity[1] = fix_all;
      m.particles.v[1][0]                           = 0.01;
      m.set_timestep(1e-8);
    }
  };
} // namespace

TEST_CASE("modifiable properties are read and set during a run, the rest refused",
          "[properties]")
{
  Threads one(1);
  Pair    p;
  auto   &grp = p.m.group(p.g);
  p.m.cycle(200); // opening 2e-8 m: sigma = kn g = 4e-4 * ... far below 1 GPa
  REQUIRE(p.m.cracks.empty());
  // Lower the tensile strength while cycling (memo Table 5: modifiable).
  grp.set_property(0, "fj_ten", 1.0);
  CHECK(grp.property(0, "fj_ten") == 1.0);
  p.m.cycle(1);
  REQUIRE(p.m.cracks.size() == 2); // both elements, in tension
  CHECK(p.m.cracks[0].type == BondType::flat_joint);
  CHECK(p.m.cracks[0].mode == 0);
  // Derived constants follow a change (tan phi once, not per step).
  grp.set_property(0, "fj_fa", 40);
  CHECK(p.m.typed_group<FlatJointLaw<2>>(p.g).properties(0).tan_fa ==
        Approx(std::tan(40 * M_PI / 180)).epsilon(1e-15));
  // Fixed before cycling, out of range, unknown: refused, naming the key.
  CHECK_THROWS_WITH(grp.set_property(0, "fj_rmul", 0.5),
                    Catch::Matchers::Contains("fj_rmul"));
  CHECK_THROWS_WITH(grp.set_property(0, "fj_kn", -1), Catch::Matchers::Contains("fj_kn"));
  CHECK_THROWS_AS(grp.property(0, "fj_nonsense"), InputError);
  CHECK(grp.property_modifiable("fj_coh"));
  CHECK_FALSE(grp.property_modifiable("fj_mtype"));
}

TEST_CASE("property blocks go into checkpoints and come back bit for bit", "[properties]")
{
  Threads one(1);
  Pair    a;
  a.m.cycle(50);
  a.m.group(a.g).set_property(0, "fj_coh", 123456.0);
  const std::string f =
      (std::filesystem::temp_directory_path() / "demfem_props_checkpoint.h5").string();
  write_checkpoint(a.m, f, {});
  Pair b; // the same set-up, another state
  read_checkpoint(b.m, f, nullptr);
  std::filesystem::remove(f);
  CHECK(b.m.group(b.g).props_data() == a.m.group(a.g).props_data());
  CHECK(b.m.group(b.g).property(0, "fj_coh") == 123456.0);
  a.m.cycle(100);
  b.m.cycle(100);
  CHECK(std::memcmp(a.m.particles.x[1].data(), b.m.particles.x[1].data(),
                    2 * sizeof(double)) == 0);
}

TEST_CASE("a smooth-joint crack has the smooth-joint type and the joint normal",
          "[properties]")
{
  Threads      one(1);
  Model<2>     m;
  const double r = 1e-3;
  m.particles.add(Vec<2>(0, 0), r, 2650);
  m.particles.add(Vec<2>(2 * r, 0), r, 2650);
  SmoothJointLaw<2>::Params q;
  q.sj_kn     = 1e13;
  q.sj_ks     = 1e13;
  q.sj_ten    = 1e6;
  q.sj_coh    = 1e9;
  q.dip       = 60; // joint normal (sin 60, cos 60): not the contact normal x
  q.bonded    = true;
  const int g = m.add_law<SmoothJointLaw<2>>(q, "joint");
  m.install(0, 1, g);
  m.particles.fixity[0] = m.particles.fixity[1] = fix_all;
  m.particles.v[1]                              = Vec<2>(0.02, 0.02 * std::sqrt(3.0));
  m.set_timestep(1e-8);
  for (int i = 0; i < 10000 && m.cracks.empty(); ++i)
    m.step();
  REQUIRE(m.cracks.size() == 1);
  const auto &c = m.cracks[0];
  CHECK(c.type == BondType::smooth_joint);
  const Vec<2> nj(std::sin(M_PI / 3), std::cos(M_PI / 3));
  CHECK(std::abs(std::abs(c.normal.dot(nj)) - 1) < 1e-12);
  CHECK(std::string(bond_type_name(c.type)) == "smooth_joint");
}
