// The region as the calibrated material (coupling/region_genesis.cc;
// docs/tunnel.md, "The region is the calibrated material"): packed by the
// calibration's genesis in a box, carved to the ring, finalized by the
// calibration's code. Every microproperty of the material reaches the
// region, the rim is as dense as the inside, and the region starts free of
// force.
#include <catch2/catch.hpp>

#include "coupling/dem_region.h"
#include "coupling/genesis_cache.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/measure/measurement.h"
#include "dem/specimen/genesis.h"

#include <cmath>
#include <cstring>
#include <functional>
#include <sstream>
#include <vector>

using namespace demfem;
using namespace demfem::coupling;

namespace
{
  // A flat-jointed material with everything a material file can carry: two
  // disjoint size pieces (half the volume each), bonded / gapped / slit
  // joints 60 / 20 / 20 %, gapped-joint gaps, non-uniform radius multipliers
  // (code 1), strengths with spread, an installation gap of 4 % of a grain.
  dem::MaterialParams rich_material()
  {
    dem::MaterialParams m;
    m.type         = "flatjointed";
    m.sizes        = {dem::SizePiece{false, 0.06, 0.08, 0, 0, 0.5},
                      dem::SizePiece{false, 0.10, 0.12, 0, 0, 0.5}};
    m.lnm_emod     = 20e9;
    m.lnm_krat     = 1.5;
    m.lnm_fric     = 0.4;
    m.emod         = 20e9;
    m.krat         = 2.0;
    m.fric         = 0.6;
    m.fj_B         = 0.6;
    m.fj_G         = 0.2;
    m.fj_gap       = {2e-4, 5e-5};
    m.fj_rmul_code = 1;
    m.fj_ten       = {4e6, 1e6};
    m.fj_coh       = {20e6, 4e6};
    m.fj_fa        = 30;
    m.igap         = 4e-3;
    m.Pm           = 20e6;
    return m;
  }

  RegionParams region_params(const dem::MaterialParams &m, double b = 1.0)
  {
    RegionParams p;
    p.radius   = b;
    p.d_lo     = 0.06;
    p.d_hi     = 0.12;
    p.seed     = 4321;
    p.material = m;
    return p;
  }

  struct Region2D
  {
    dem::Model<2>      model;
    RegionGroups       groups;
    std::ostringstream log; // build_region's progress lines
  };
  // The region of radius b inside a ring of n straight segments.
  void build(Region2D &r, const RegionParams &p, unsigned int n = 64)
  {
    auto            &W    = r.model.walls;
    const int        wall = W.add_wall("ring");
    std::vector<int> v(n);
    for (unsigned int k = 0; k < n; ++k)
      v[k] = W.add_vertex(dem::Vec<2>(p.radius * std::cos(2 * M_PI * k / n),
                                      p.radius * std::sin(2 * M_PI * k / n)));
    for (unsigned int k = 0; k < n; ++k)
      W.add_facet(wall, {{v[k], v[(k + 1) % n]}});
    r.groups = build_region<2>(r.model, p, &r.log);
  }

  // Clearance of grain i from the ring (smallest distance from its surface
  // to a facet).
  double ring_clearance(const dem::Model<2> &m, std::size_t i)
  {
    const auto &P = m.particles;
    double      c = HUGE_VAL;
    for (std::size_t f = 0; f < m.walls.n_facets(); ++f)
      {
        std::array<double, 2> w;
        c = std::min(c,
                     (m.walls.closest_point(f, P.x[i], w) - P.x[i]).norm() - P.radius[i]);
      }
    return c;
  }

  const Region2D &rich_region()
  {
    static const Region2D r = [] {
      Region2D out;
      build(out, region_params(rich_material()));
      return out;
    }();
    return r;
  }

  const dem::ContactGroup<2, dem::FlatJointLaw<2>> &joints(const dem::Model<2> &m)
  {
    using FJ = dem::FlatJointLaw<2>;
    for (int g = 0; g < m.n_groups(); ++g)
      if (std::strcmp(m.group(g).law_name(), FJ::name) == 0 && m.group(g).size() > 0)
        return static_cast<const dem::ContactGroup<2, FJ> &>(m.group(g));
    throw std::runtime_error("no flat-joint group");
  }

  // Porosity of the annulus r0 <= |x| < r1 (points of a fine grid, overlaps
  // counted once): the fraction of grid points no grain covers.
  double annulus_porosity(const dem::Particles<2> &P, double r0, double r1, double h)
  {
    std::size_t in = 0, covered = 0;
    for (double x = -r1; x <= r1; x += h)
      for (double y = -r1; y <= r1; y += h)
        {
          const double r = std::hypot(x, y);
          if (r < r0 || r >= r1)
            continue;
          ++in;
          for (std::size_t i = 0; i < P.size(); ++i)
            if ((P.x[i] - dem::Vec<2>(x, y)).squaredNorm() < P.radius[i] * P.radius[i])
              {
                ++covered;
                break;
              }
        }
    return 1.0 - double(covered) / double(in);
  }
} // namespace

TEST_CASE("region genesis: the material's B/G/S fractions, gaps and radius multipliers",
          "[coupling][region-genesis]")
{
  const auto &r = rich_region();
  const auto  c = dem::contact_counts(r.model);
  INFO(c.grains << " grains, " << c.fj << " joints: B " << c.fj_bonded << " G "
                << c.fj_gapped << " S " << c.fj_slit);
  REQUIRE(c.grains > 150);
  REQUIRE(c.fj > 300);
  // fistPkg §2.6.2 Eq. 1: n_B = phi_B n, n_G = phi_G n (rounded) over the
  // joints the finalization installed; the rattlers removed afterwards take
  // none (they have no joint).
  CHECK(std::abs(c.fj_bonded - 0.6 * c.fj) <= 0.5);
  CHECK(std::abs(c.fj_gapped - 0.2 * c.fj) <= 0.5);
  CHECK(c.fj_bonded + c.fj_gapped + c.fj_slit == c.fj);
  // Gapped joints' g_o drawn from N(2e-4, 5e-5): mean within 3 standard errors.
  const auto &grp  = joints(r.model);
  double      gsum = 0;
  for (std::size_t k = 0; k < grp.size(); ++k)
    gsum += grp.properties(k).mtype == 2 ? grp.properties(k).gap0 : 0.0;
  CHECK(gsum / c.fj_gapped ==
        Approx(2e-4).margin(3 * 5e-5 / std::sqrt(double(c.fj_gapped))));
  // Non-uniform radius multipliers (code 1): at most 1, not all equal.
  double rmin = HUGE_VAL, rmax = 0;
  for (std::size_t k = 0; k < grp.size(); ++k)
    {
      rmin = std::min(rmin, grp.properties(k).rmul);
      rmax = std::max(rmax, grp.properties(k).rmul);
    }
  CHECK(rmax <= 1.0);
  CHECK(rmin < rmax);
}

TEST_CASE("region genesis: per-contact strengths with the material's mean and spread",
          "[coupling][region-genesis]")
{
  const auto &grp = joints(rich_region().model);
  const auto  n   = double(grp.size());
  double      s = 0, s2 = 0, c = 0;
  for (std::size_t k = 0; k < grp.size(); ++k)
    {
      s += grp.properties(k).ten;
      s2 += grp.properties(k).ten * grp.properties(k).ten;
      c += grp.properties(k).coh;
    }
  const double mean = s / n, sd = std::sqrt(s2 / n - mean * mean);
  INFO(n << " joints: tensile strength mean " << mean << " sd " << sd
         << ", cohesion mean " << c / n);
  // Normal draws truncated at zero 4 sd below the mean (a negligible cut):
  // means within 3 standard errors, the sd within 15 % (its standard error
  // is sd / sqrt(2 n) < 4 % for n > 300).
  CHECK(mean == Approx(4e6).margin(3 * 1e6 / std::sqrt(n)));
  CHECK(c / n == Approx(20e6).margin(3 * 4e6 / std::sqrt(n)));
  CHECK(sd == Approx(1e6).epsilon(0.15));
}

TEST_CASE("region genesis: both size pieces and the installation gap",
          "[coupling][region-genesis]")
{
  const auto &r = rich_region();
  const auto &P = r.model.particles;
  // Grain scaling multiplies every diameter by one factor; the two pieces
  // stay disjoint (a grain shrunk onto the ring may fall into the gap
  // between them: at most the few on the ring).
  double dmax = 0;
  for (double x : P.radius)
    dmax = std::max(dmax, 2 * x);
  const double s       = dmax / 0.12;
  std::size_t  between = 0;
  double       small = 0, all = 0;
  for (double x : P.radius)
    {
      const double d = 2 * x;
      between += d > s * 0.08 * (1 + 1e-9) && d < s * 0.10 * (1 - 1e-9);
      all += d * d;
      small += d < s * 0.09 ? d * d : 0.0;
    }
  INFO("scale " << s << ", " << between << " grains between the pieces");
  CHECK(s == Approx(1.0).margin(0.1));
  CHECK(between <= r.model.particles.size() / 20);
  // Half the grain volume in each piece: the carving takes a disk out of a
  // box packed with both, the last grain of each piece shifts it by < 1 %.
  CHECK(small / all == Approx(0.5).margin(0.05));
  // Installation gap g_i = 4 mm: grains apart by up to g_i are bonded, none
  // farther, except a grain shrunk or moved onto the ring, which keeps the
  // bonds of its packing contacts across the gap that opened (next test).
  // Grains off the ring: clearance above 1 um (those shrunk onto it keep
  // 1e-7 of their overlap, far below).
  const auto &grp   = joints(r.model);
  double      gmax  = -HUGE_VAL;
  std::size_t apart = 0;
  for (std::size_t k = 0; k < grp.size(); ++k)
    {
      const auto i = grp.end1[k], j = grp.end2[k];
      if (ring_clearance(r.model, i) < 1e-6 || ring_clearance(r.model, j) < 1e-6)
        continue;
      const double g = (P.x[j] - P.x[i]).norm() - P.radius[i] - P.radius[j];
      gmax           = std::max(gmax, g);
      apart += g > 0 ? 1 : 0;
    }
  INFO(apart << " of " << grp.size() << " joints across a gap, largest " << gmax << " m");
  CHECK(apart > 0.05 * grp.size());
  CHECK(gmax <= 4e-3 * (1 + 1e-9));
  CHECK(gmax > 0.5 * 4e-3);
}

TEST_CASE("region genesis: the carved region starts free of force, inside the ring",
          "[coupling][region-genesis]")
{
  Region2D r;
  build(r, region_params(rich_material()));
  const auto &P = r.model.particles;
  // Every grain inside the ring polygon: its centre within the inscribed
  // circle, its edge not beyond the chords (shrunk onto them).
  const double inner = std::cos(M_PI / 64);
  for (std::size_t i = 0; i < P.size(); ++i)
    CHECK(P.x[i].norm() < inner);
  r.model.step();
  // Bonds installed at their gaps carry nothing; grains on the ring were
  // shrunk by their overlap (times 1 + 1e-7), so no contact is loaded. The
  // packing's forces were of order Pm d = 20e6 x 0.09 = 1.8e6 N/m.
  const double fmax = dem::max_contact_force(r.model);
  INFO("largest contact force after one step " << fmax << " N/m");
  CHECK(fmax <= 1e-9 * 20e6 * 0.09);
}

TEST_CASE("region genesis: grains shrunk or moved onto the ring keep their bonds and "
          "touch it",
          "[coupling][region-genesis]")
{
  // A grain shrunk onto the ring by more than the installation gap was
  // left without a bond, removed as a rattler, and the ring kept almost no
  // contacts (measured on the 1 m verification region: one; a wall-facet
  // ring then carried nothing). Now every grain the carving shrank stays,
  // touching the ring, with at least one bond; and so does every rim grain
  // moved onto it (close_rim), which before lay up to a radius inside.
  const auto       &r            = rich_region();
  const std::string log          = r.log.str();
  auto              count_before = [&](const std::string &what) {
    const auto at = log.find(what);
    REQUIRE(at != std::string::npos);
    const auto from = log.find_last_of("(,", at) + 1;
    return std::stol(log.substr(from, at - from));
  };
  INFO(log);
  const long       shrunk = count_before(" shrunk onto the ring");
  const long       moved  = count_before(" moved onto the ring");
  const auto      &P      = r.model.particles;
  const auto      &grp    = joints(r.model);
  std::vector<int> bonds(P.size(), 0);
  for (std::size_t k = 0; k < grp.size(); ++k)
    ++bonds[grp.end1[k]], ++bonds[grp.end2[k]];
  long touching = 0, unbonded = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (ring_clearance(r.model, i) < 1e-6)
      {
        ++touching;
        unbonded += bonds[i] == 0;
      }
  INFO(shrunk << " grains shrunk onto the ring, " << moved << " moved onto it, "
              << touching << " touch it");
  REQUIRE(shrunk > 10);
  // Most of the rim reaches the ring (measured 32 moved against 17 shrunk).
  CHECK(moved > shrunk);
  CHECK(touching == shrunk + moved);
  CHECK(unbonded == 0);
}

TEST_CASE("region genesis: the rim is as dense as the inside (no wall layer)",
          "[coupling][region-genesis]")
{
  const auto  &r   = rich_region();
  const auto  &P   = r.model.particles;
  const double d   = 0.12; // largest grain
  const double in  = annulus_porosity(P, 0, 1.0 - 2 * d, 0.004),
               rim = annulus_porosity(P, 1.0 - 2 * d, 1.0 - d, 0.004);
  INFO("porosity inside " << in << ", second grain layer from the ring " << rim);
  // Packed against a wall, the outer two grains of a frictionless packing
  // are 0.07-0.1 looser than the inside (measured on the packing this
  // replaced: 0.27 against 0.15-0.20). Carved from a larger packing, only
  // the last grain layer is cut (grains shrunk onto the ring: measured
  // porosity 0.21 at 1 - d .. 1 - d/2); the layer behind it is the
  // packing's: within 0.03 (the scatter of a one-grain annulus of about 60
  // grains; measured 0.16 against 0.15).
  CHECK(std::abs(rim - in) < 0.03);
}

TEST_CASE("region genesis: the 3D slab carved from the material genesis lies in the "
          "slab, starts free of force and carries the material's fractions",
          "[coupling][region-genesis][region3d]")
{
  // Radius 0.6 m, the rich material's two size pieces, slab 0.3 m: a
  // box of 1.68 x 1.68 x 0.3 m packed (about 900 spheres), about 500 kept.
  RegionParams p         = region_params(rich_material(), 0.6);
  p.slab_thickness       = 0.3;
  dem::MaterialParams &m = *p.material;
  m.fj_Nal               = 4;
  dem::Model<3> model;
  add_cylinder_ring(model.walls, p.radius, p.slab_thickness, 20, 2, "ring");
  std::ostringstream log;
  const RegionGroups G = build_region<3>(model, p, &log);
  const auto        &P = model.particles;
  REQUIRE(P.size() > 200);
  // The rim closed onto the ring in 3D as in 2D: at least the grains moved
  // onto it touch the ring's (vertical) facets, within round-off.
  {
    INFO(log.str());
    const auto at = log.str().find(" moved onto the ring");
    REQUIRE(at != std::string::npos);
    const auto from     = log.str().find_last_of(",", at) + 1;
    const long moved    = std::stol(log.str().substr(from, at - from));
    long       touching = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        double c = HUGE_VAL;
        for (std::size_t f = 0; f < model.walls.n_facets(); ++f)
          if (model.walls.facet_wall[f] != G.slab_walls[0] &&
              model.walls.facet_wall[f] != G.slab_walls[1])
            {
              std::array<double, 3> w;
              c = std::min(c, (model.walls.closest_point(f, P.x[i], w) - P.x[i]).norm() -
                                  P.radius[i]);
            }
        touching += c < 1e-6;
      }
    INFO(moved << " grains moved onto the ring, " << touching << " touch it");
    CHECK(moved > 0);
    CHECK(touching >= moved);
  }
  // Every grain inside the slab walls and the ring's inscribed circle
  // (chords of 20 facets: cos(pi / 20) of the radius), shrunk onto them
  // where it crossed.
  const double inner = p.radius * std::cos(M_PI / 20);
  for (std::size_t i = 0; i < P.size(); ++i)
    {
      CHECK(P.x[i][2] - P.radius[i] >= -1e-12);
      CHECK(P.x[i][2] + P.radius[i] <= p.slab_thickness + 1e-12);
      CHECK(P.x[i].head<2>().norm() < inner);
    }
  model.step();
  // Force-free start, as in 2D: the packing's forces were of order
  // Pm d^2 = 20e6 x 0.09^2 = 1.6e5 N.
  double fmax = 0;
  for (int g = 0; g < model.n_groups(); ++g)
    for (std::size_t k = 0; k < model.group(g).size(); ++k)
      fmax = std::max(fmax, model.group(g).force[k].norm());
  INFO("largest contact force after one step " << fmax << " N");
  CHECK(fmax <= 1e-9 * 20e6 * 0.09 * 0.09);
  // fistPkg §2.6.2 Eq. 1 in 3D too.
  const auto c = dem::contact_counts(model);
  INFO(c.fj << " joints: B " << c.fj_bonded << " G " << c.fj_gapped << " S "
            << c.fj_slit);
  REQUIRE(c.fj > 300);
  CHECK(std::abs(c.fj_bonded - 0.6 * c.fj) <= 0.5);
  CHECK(std::abs(c.fj_gapped - 0.2 * c.fj) <= 0.5);
  CHECK(G.genesis_steps > 0);
  CHECK(G.n_bonds == std::size_t(c.fj));
}

TEST_CASE("region genesis: a sweep reuses the packing, bit for bit",
          "[coupling][genesis]")
{
  // The genesis is deterministic, so a run with the same packing inputs
  // carves its region out of the kept box (coupling/genesis_cache.h) and
  // gets the region a fresh packing gives, exactly: the same grains, the
  // same bonds, the same genesis random stream for the finalization.
  clear_packed_boxes();
  const RegionParams p = region_params(rich_material(), 0.8);
  Region2D           a, b;
  build(a, p);
  build(b, p);
  CHECK_FALSE(a.groups.genesis_reused);
  CHECK(b.groups.genesis_reused);
  CHECK(b.log.str().find("is reused") != std::string::npos);
  CHECK(b.groups.genesis_steps == a.groups.genesis_steps);
  CHECK(b.groups.genesis_wall_time_s == a.groups.genesis_wall_time_s);
  const auto &Pa = a.model.particles, &Pb = b.model.particles;
  REQUIRE(Pb.size() == Pa.size());
  bool same = true;
  for (std::size_t i = 0; i < Pa.size(); ++i)
    same = same && Pa.x[i] == Pb.x[i] && Pa.radius[i] == Pb.radius[i] &&
           Pa.id[i] == Pb.id[i];
  CHECK(same);
  CHECK(b.groups.n_bonds == a.groups.n_bonds);
  CHECK(b.groups.porosity == a.groups.porosity);
  const auto &Ja = joints(a.model), &Jb = joints(b.model);
  REQUIRE(Jb.size() == Ja.size());
  CHECK(Ja.props_data() == Jb.props_data()); // strengths, gaps, multipliers

  // Strengths are the finalization's: another tensile strength reuses the
  // box, and its bonds differ.
  RegionParams q     = p;
  q.material->fj_ten = {6e6, 1e6};
  Region2D c;
  build(c, q);
  CHECK(c.groups.genesis_reused);
  CHECK(c.model.particles.size() == Pa.size());

  // Another seed is another packing.
  RegionParams s = p;
  s.seed         = p.seed + 1;
  Region2D d;
  build(d, s);
  CHECK_FALSE(d.groups.genesis_reused);

  // Every packing input is in the key: a change of any one packs anew
  // (dem::pack_specimen reads these; genesis_cache.cc, packing_key).
  const std::vector<std::pair<const char *, std::function<void(dem::MaterialParams &)>>>
      inputs = {{"Pm", [](auto &m) { m.Pm *= 1.5; }},
                {"lnm_emod", [](auto &m) { m.lnm_emod *= 1.5; }},
                {"lnm_krat", [](auto &m) { m.lnm_krat *= 1.5; }},
                {"emod", [](auto &m) { m.emod *= 1.5; }},
                {"density", [](auto &m) { m.density *= 1.5; }},
                {"local_damping", [](auto &m) { m.local_damping = 0.5; }},
                {"diameter_multiplier", [](auto &m) { m.diameter_multiplier = 0.9; }},
                {"sizes", [](auto &m) { m.sizes[1].d_hi = 0.11; }},
                {"ratio_limit", [](auto &m) { m.ratio_limit = 4e-3; }},
                {"P_tol", [](auto &m) { m.P_tol = 5e-3; }}};
  for (const auto &[name, change] : inputs)
    {
      RegionParams v = p;
      change(*v.material);
      Region2D r;
      build(r, v);
      INFO("changed " << name);
      CHECK_FALSE(r.groups.genesis_reused);
    }

  // A run that would reuse a box is still refused for its own bad keys.
  RegionParams bad     = p;
  bad.material->fj_ten = {-1e6, 0};
  Region2D e;
  CHECK_THROWS_AS(build(e, bad), dem::InputError);
  clear_packed_boxes();
}
