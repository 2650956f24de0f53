// The region as the calibrated material (docs/tunnel.md, "The region is the
// calibrated material"): the calibration's genesis packs the material in a
// box around the region (dem::pack_specimen, fistPkg §4.2.1), the region is
// carved out of the packing, and the calibration's finalization installs the
// bonds (dem::finalize_specimen, §4.2.2). One genesis for the lab tests and
// the region: size-distribution pieces, B/G/S fractions and gaps,
// radius-multiplier code, strength distributions and installation gap all
// come from the material, per contact (dem/specimen/property_rules.h).
//
// Why carve and not pack against the ring: grains packed against a wall
// leave a looser layer next to it (the wall effect; measured porosity 0.27
// in the outer two grains against 0.15-0.20 inside). A box larger than the
// disk by two of the largest grains on every side puts that layer outside
// the region, so the rim has the packing's density.
#include "coupling/dem_region.h"
#include "coupling/genesis_cache.h"
#include "dem/laws/linear_law.h"
#include "dem/measure/measurement.h"
#include "dem/specimen/genesis.h"
#include "dem/specimen/property_rules.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace demfem::coupling
{
  namespace
  {
    // How far close_rim moves a rim grain onto the ring, in its radii. One
    // radius closed 63 % of the perimeter of the 1 m verification region
    // (79 of about 126 grain places, 4-6 cm grains); 1.5 radii also moves
    // a grain of the second row into a place the carving emptied (a grain
    // more than half outside left out), 73 %: the patch test's largest
    // radial-strain jump at the ring fell from 0.05-0.08 to 0.024-0.039
    // over four packing seeds (tests/coupling/patch_test.cc). Two radii
    // moved no more grains.
    constexpr double rim_reach = 1.5;

    // The carved grains before they enter the region's model.
    template <int dim>
    struct RimGrains
    {
      std::vector<dem::Vec<dim>> x;
      std::vector<double>        r, density;
      std::vector<double>        shrunk;   // radius lost to the ring (shrinking), or
                                           // distance moved onto it (close_rim)
      std::vector<double>        ring_gap; // gap to the ring (0: touching it)
      std::vector<dem::Vec<dim>> toward;   // in-plane unit vector to the ring's
                                           // closest point
    };

    // Gap between a grain and the ring's facets (3D: not the slab walls) and
    // the in-plane direction to the closest facet point; HUGE_VAL when the
    // grain lies more than rim_reach radii inside the inscribed circle (it cannot
    // be a rim grain, close_rim).
    template <int dim>
    std::pair<double, dem::Vec<dim>> ring_gap_of(const dem::Walls<dim> &W,
                                                 const RegionGroups    &G,
                                                 const dem::Vec<dim> &x, double r,
                                                 double inner)
    {
      std::pair<double, dem::Vec<dim>> best{HUGE_VAL, dem::Vec<dim>::Zero()};
      if (x.template head<2>().norm() + (1 + rim_reach) * r < inner * (1 - 1e-12))
        return best;
      for (std::size_t f = 0; f < W.n_facets(); ++f)
        if (dim == 2 ||
            (W.facet_wall[f] != G.slab_walls[0] && W.facet_wall[f] != G.slab_walls[1]))
          {
            std::array<double, dim> w;
            dem::Vec<dim>           d = W.closest_point(f, x, w) - x;
            if constexpr (dim == 3)
              d[2] = 0; // the ring's facets are vertical: move in the plane
            const double g = d.norm() - r;
            if (g < best.first)
              best = {g, d / std::max(d.norm(), 1e-300)};
          }
      return best;
    }

    // How far grain i can move along e before it overlaps a grain of its
    // angular bin or the two next to it by more than `allowed_overlap` (or
    // by more than it does now).
    template <int dim>
    double blocked_at(const RimGrains<dim>                        &rim,
                      const std::vector<std::vector<std::size_t>> &bins, int b0,
                      std::size_t i, const dem::Vec<dim> &e, double allowed_overlap)
    {
      const int n_bin = static_cast<int>(bins.size());
      double    s     = HUGE_VAL;
      for (int db = -1; db <= 1; ++db)
        {
          if (n_bin < 3 && db != 0)
            continue;
          for (const std::size_t j : bins[(b0 + db + n_bin) % n_bin])
            {
              // Smallest s at which |x_i + s e - x_j| falls to D.
              const dem::Vec<dim> dx   = rim.x[j] - rim.x[i];
              const double        dist = dx.norm();
              const double D     = std::min(dist, rim.r[i] + rim.r[j] - allowed_overlap);
              const double ahead = dx.dot(e);
              const double disc  = ahead * ahead - dist * dist + D * D;
              if (j == i || ahead <= 0 || disc < 0)
                continue;
              s = std::min(s, std::max(0.0, ahead - std::sqrt(disc)));
            }
        }
      return s;
    }

    // Closes the rim onto the ring (docs/tunnel.md, "The region is the
    // calibrated material", step 2). A region carved out of a packing
    // touches the ring only where grains were shrunk onto it; the rest of
    // its rim lies up to a grain radius inside, so a ring of wall facets (or
    // the reference's membrane) would load the region at a few points. Each
    // rim grain whose gap to the ring is at most rim_reach radii is moved onto
    // the ring along the direction to it, unless another grain blocks the
    // way. Grains nearest the ring move first, so a grain behind another
    // stays blocked. A grain in contact with a neighbour beside it must pass
    // it: the pair may overlap by up to `allowed_overlap` (the packing's
    // mean overlap, so the rim stays within the packing's own overlaps). The
    // distance moved is added to `shrunk`: the finalization bonds the
    // packing contacts the move opened (pairs within g_i + shrunk_i +
    // shrunk_j, dem::finalize_specimen). Returns the number of grains moved
    // and of those blocked.
    template <int dim>
    std::pair<std::size_t, std::size_t> close_rim(RimGrains<dim>        &rim,
                                                  const dem::Walls<dim> &W,
                                                  const RegionGroups &G, double inner,
                                                  double allowed_overlap)
    {
      const std::size_t n = rim.x.size();
      if (n == 0)
        return {0, 0};
      const double r_max = *std::max_element(rim.r.begin(), rim.r.end());
      // Blockers: grains within 2 + 2 rim_reach of the largest radii of the
      // ring, binned by angle so that each candidate checks its bin and the
      // two next to it (a blocker lies within (2 + rim_reach) r_max of the
      // candidate).
      const double band  = inner - (2 + 2 * rim_reach) * r_max;
      const double reach = (2 + 2 * rim_reach) * r_max / std::max(band, 1e-300);
      const int    n_bin = band > 0 ? std::max(1, static_cast<int>(2 * M_PI / reach)) : 1;
      auto         bin_of = [&](const dem::Vec<dim> &x) {
        const double th = std::atan2(x[1], x[0]) + M_PI; // [0, 2 pi]
        return std::min(n_bin - 1, static_cast<int>(th / (2 * M_PI) * n_bin));
      };
      std::vector<std::vector<std::size_t>> bins(n_bin);
      std::vector<std::size_t>              candidates;
      for (std::size_t i = 0; i < n; ++i)
        {
          if (rim.x[i].template head<2>().norm() + rim.r[i] > band)
            bins[bin_of(rim.x[i])].push_back(i);
          if (rim.ring_gap[i] > 0 && rim.ring_gap[i] <= rim_reach * rim.r[i])
            candidates.push_back(i);
        }
      std::sort(candidates.begin(), candidates.end(), [&](std::size_t a, std::size_t b) {
        return rim.ring_gap[a] < rim.ring_gap[b];
      });
      std::size_t moved = 0, blocked = 0;
      for (const std::size_t i : candidates)
        {
          // Two passes: the ring is a polygon, so a move toward the closest
          // point of one facet can leave a residual gap near a vertex. Each
          // move stops 1e-7 of the gap short of the ring (as the shrinking
          // does): the grain touches it free of force. A grain that cannot
          // reach the ring stays where it is (moving it part of the way
          // would open gaps behind it and gain no contact).
          const dem::Vec<dim> x_was = rim.x[i], toward_was = rim.toward[i];
          const double        gap_was  = rim.ring_gap[i];
          double              total    = 0;
          auto                try_move = [&](const dem::Vec<dim> &e, double want) {
            if (total + want > rim_reach * rim.r[i] ||
                blocked_at(rim, bins, bin_of(rim.x[i]), i, e, allowed_overlap) < want)
              return false;
            rim.x[i] += want * e;
            total += want;
            std::tie(rim.ring_gap[i], rim.toward[i]) =
                ring_gap_of(W, G, rim.x[i], rim.r[i], inner);
            rim.ring_gap[i] = std::max(rim.ring_gap[i], 0.0);
            return true;
          };
          // Blocked on the direct way: a grain beside it may leave room at
          // a slant. Directions tilted by 15, 30 and 45 degrees either side,
          // each to the inscribed circle (the polygon's residual is closed
          // by the direct passes below).
          if (blocked_at(rim, bins, bin_of(rim.x[i]), i, rim.toward[i], allowed_overlap) <
              rim.ring_gap[i] * (1 - 1e-7))
            for (int k = 1; k <= 6; ++k)
              {
                const double  a = (k % 2 ? 1 : -1) * ((k + 1) / 2) * M_PI / 12;
                dem::Vec<dim> e = dem::Vec<dim>::Zero();
                e[0] = std::cos(a) * rim.toward[i][0] - std::sin(a) * rim.toward[i][1];
                e[1] = std::sin(a) * rim.toward[i][0] + std::cos(a) * rim.toward[i][1];
                // |x + s e| = inner - r in the plane.
                const dem::Vec<2> x  = rim.x[i].template head<2>();
                const double      xe = x.dot(e.template head<2>());
                const double      c  = std::pow(inner - rim.r[i], 2) - x.squaredNorm();
                const double      sq = xe * xe + c;
                if (c <= 0 || sq < 0)
                  break; // already at the inscribed circle
                if (try_move(e, (-xe + std::sqrt(sq)) * (1 - 1e-7)))
                  break;
              }
          for (int pass = 0; pass < 2 && rim.ring_gap[i] > 1e-6 * rim.r[i]; ++pass)
            if (!try_move(rim.toward[i], rim.ring_gap[i] * (1 - 1e-7)))
              break;
          if (total > 0 && rim.ring_gap[i] > 1e-6 * rim.r[i])
            { // a slanted move the direct passes could not complete: undo
              rim.x[i]        = x_was;
              rim.toward[i]   = toward_was;
              rim.ring_gap[i] = gap_was;
              total           = 0;
            }
          rim.shrunk[i] += total;
          moved += total > 0;
          blocked += total == 0;
        }
      return {moved, blocked};
    }
  } // namespace

  template <int dim>
  RegionGroups carve_region(dem::Model<dim> &m, const RegionParams &p, double inner,
                            RegionGroups G, std::ostream *progress)
  {
    using LN                = dem::LinearLaw<dim>;
    dem::MaterialParams mat = p.genesis_material();
    mat.seed                = p.seed;
    mat.memory_limit        = p.memory_limit;
    const double t          = dim == 3 ? p.slab_thickness : 1.0;

    // The box: the disk's circumscribed square widened by two of the
    // largest grains on each side (the vessel's looser wall layer stays
    // outside the region); 3D: the slab's thickness along z (the box's
    // axial walls are the slab walls, both frictionless and fixed during
    // grain scaling).
    dem::VesselParams v;
    v.shape = "box";
    v.W     = 2 * (inner + 2 * p.d_hi);
    if constexpr (dim == 2)
      v.H = v.W;
    else
      {
        v.D = v.W;
        v.H = t;
      }
    bool       reused = false;
    const auto box    = [&] {
      try
        {
          return packed_box<dim>(mat, v, progress, "DEM region (material genesis)",
                                 reused);
        }
      catch (const dem::PackingDiverged &e)
        {
          throw std::runtime_error(
                 std::string("DEM region: the packing diverged (non-finite forces): the "
                                "contact moduli (DEM region/emod, lnm emod, or the material "
                                "file's) are out of any physical range (") +
                 e.what() + ")");
        }
    }();
    dem::Random rng       = box->rng; // the genesis stream, continued by the finalization
    G.max_overlap_ratio   = box->max_overlap_ratio;
    G.mean_overlap_ratio  = box->mean_overlap_ratio;
    G.genesis_steps       = box->steps;
    G.genesis_reused      = reused;
    G.genesis_wall_time_s = box->wall_time_s;

    // Carve: the grains whose centres lie inside the ring, each shrunk by
    // its largest overlap with the region's walls (the ring; 3D also the
    // slab walls) so that no grain-wall contact carries force at the start
    // (fistPkg §4.2.2 moves a vessel's walls instead; the ring is the
    // continuum's boundary and cannot move). A grain more than half outside
    // would shrink below half its size: it is left out instead.
    const auto    &Q     = *box;
    auto          &W     = m.walls;
    std::size_t    n_cut = 0, n_shrunk = 0;
    RimGrains<dim> rim; // the carved grains, before they enter the model
    for (std::size_t i = 0; i < Q.x.size(); ++i)
      {
        dem::Vec<dim> x = Q.x[i];
        if constexpr (dim == 3)
          x[2] += 0.5 * t; // the vessel is centred at z = 0, the slab at t/2
        if (x.template head<2>().norm() >= inner)
          continue;
        const auto [ring_gap, toward] = ring_gap_of(W, G, x, Q.radius[i], inner);
        double gap                    = ring_gap;
        if constexpr (dim == 3)
          gap = std::min({gap, x[2] - Q.radius[i], t - x[2] - Q.radius[i]});
        double r = Q.radius[i];
        if (gap < 0)
          {
            r += gap * (1 + 1e-7);
            if (r < 0.5 * Q.radius[i])
              {
                ++n_cut;
                continue;
              }
            ++n_shrunk;
          }
        rim.x.push_back(x);
        rim.r.push_back(r);
        rim.density.push_back(Q.mass[i] / dem::ball_volume<dim>(Q.radius[i]));
        rim.shrunk.push_back(Q.radius[i] - r);
        rim.ring_gap.push_back(gap < 0 ? 0.0 : ring_gap);
        rim.toward.push_back(toward);
      }
    double r_mean = 0;
    for (double r : Q.radius)
      r_mean += r / Q.radius.size();
    const auto [n_moved, n_blocked] =
        close_rim(rim, W, G, inner, G.mean_overlap_ratio * r_mean);
    for (std::size_t i = 0; i < rim.x.size(); ++i)
      m.particles.add(rim.x[i], rim.r[i], rim.density[i]);
    if (progress)
      *progress << "DEM region: " << m.particles.size() << " of " << Q.x.size()
                << " packed grains carved (" << n_shrunk << " shrunk onto the ring, "
                << n_cut << " more than half outside left out, " << n_moved
                << " moved onto the ring, " << n_blocked << " blocked)\n";

    // Finalization by the calibration's code in the region's model (ring
    // walls, 3D slab walls): the packing contacts become the material's
    // linear contacts, pairs within the installation gap its bonds. A grain
    // shrunk onto the ring keeps the bonds of its packing contacts (bonded
    // across the gap the shrinking opened): without them the grains along
    // the ring became rattlers and were removed, leaving the ring without
    // contacts (measured: 1 grain-ring contact on a 1 m region).
    dem::Specimen<dim> reg;
    reg.model    = std::move(m);
    reg.material = mat;
    reg.vessel.lo.fill(-1);
    reg.vessel.hi.fill(-1);
    reg.vessel.side = -1;
    auto &rm        = reg.model;
    // Packing law (frictionless; its contacts are reinstalled by the
    // finalization) and the region's wall laws.
    G.pack =
        rm.template add_law<LN>({}, "DEM region (carved packing)",
                                dem::linear_rule<dim>({mat.lnm_emod, mat.lnm_krat}, 0.0));
    G.wall =
        rm.template add_law<LN>({}, "DEM region (ring)",
                                dem::linear_rule<dim>({mat.emod, mat.krat}, p.wall_fric));
    G.pack_wall = G.wall;
    if constexpr (dim == 3) // plane strain: frictionless, as a symmetry plane
      {
        G.slab_wall = rm.template add_law<LN>({}, "DEM region (slab walls)",
                                              dem::linear_rule<dim>({mat.emod, 0}, 0));
        std::vector<char> slab(rm.walls.n_facets(), 0);
        for (std::size_t k = 0; k < rm.walls.n_facets(); ++k)
          slab[k] = rm.walls.facet_wall[k] == G.slab_walls[0] ||
                    rm.walls.facet_wall[k] == G.slab_walls[1];
        const int law           = G.slab_wall;
        rm.new_wall_contact_law = [slab, law](std::uint32_t, std::uint32_t k) {
          return k < slab.size() && slab[k] ? law : -1;
        };
      }
    rm.set_default_law(G.pack, G.wall);
    rm.local_damping = mat.local_damping;
    rm.set_timestep(0);
    rm.invalidate_contacts();
    rm.detect_contacts();
    reg.wall_group = G.wall;
    dem::finalize_specimen(reg, rng, progress, false, rim.shrunk);
    G.linear = reg.linear_group;
    G.bond   = reg.bond_group;

    // Rattlers (grains without a bond) are removed: they carry no stress and
    // would drift into the excavation.
    auto &P = rm.particles;
    {
      std::vector<char> bonded(P.size(), 0);
      const auto       &b = rm.group(G.bond);
      for (std::size_t k = 0; k < b.size(); ++k)
        bonded[b.end1[k]] = bonded[b.end2[k]] = 1;
      std::vector<char> out(P.size(), 0);
      for (std::size_t i = 0; i < P.size(); ++i)
        G.n_rattlers += (out[i] = !bonded[i]);
      if (G.n_rattlers > 0)
        rm.remove_particles(out);
    }
    G.n_bonds = rm.group(G.bond).size();
    rm.set_default_law(G.linear, G.wall);
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        P.v[i].setZero();
        P.w[i].setZero();
        P.x0[i] = P.x[i];
      }
    rm.invalidate_contacts();
    rm.reset_energy_baseline();
    double solid = 0;
    for (double r : P.radius)
      solid += dem::ball_volume<dim>(r);
    const double volume = M_PI * inner * inner * t;
    G.porosity          = 1 - solid / volume;
    G.packed_porosity   = box->porosity;
    // The interior's porosity: the column two of the largest grains inside
    // the ring, where the carving and the rim's moves did not reach (a
    // region too small for that uses its whole porosity).
    const double r_interior = inner - 2 * p.d_hi;
    G.interior_porosity =
        r_interior > 0.3 * inner ? dem::column_porosity(rm, r_interior, t) : G.porosity;
    m = std::move(rm);
    if (progress)
      *progress << "DEM region: " << G.n_bonds << " bonds, " << G.n_rattlers
                << " rattlers removed, porosity " << G.porosity << " (interior "
                << G.interior_porosity << ", packing " << G.packed_porosity << ")\n";
    return G;
  }

  template RegionGroups carve_region<2>(dem::Model<2> &, const RegionParams &, double,
                                        RegionGroups, std::ostream *);
  template RegionGroups carve_region<3>(dem::Model<3> &, const RegionParams &, double,
                                        RegionGroups, std::ostream *);
} // namespace demfem::coupling
