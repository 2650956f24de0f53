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
#include "dem/laws/linear_law.h"
#include "dem/specimen/genesis.h"
#include "dem/specimen/property_rules.h"

#include <algorithm>
#include <cmath>

namespace demfem::coupling
{
  namespace
  {
    template <int dim>
    double ball_volume(double r)
    {
      return dim == 2 ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r;
    }

    // Largest grain-grain overlap over the mean radius, and the mean over
    // the overlapping pairs (how tight the packing is).
    template <int dim>
    std::pair<double, double> overlap_ratios(const dem::Model<dim> &m)
    {
      double      sum = 0, mx = 0, rsum = 0;
      std::size_t n = 0;
      for (double r : m.particles.radius)
        rsum += r;
      const double rmean = rsum / std::max<std::size_t>(1, m.particles.size());
      for (int g = 0; g < m.n_groups(); ++g)
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            if (!grp.is_wall[k] && grp.gap[k] < 0)
              {
                sum += -grp.gap[k];
                mx = std::max(mx, -grp.gap[k]);
                ++n;
              }
        }
      return {mx / rmean, n > 0 ? sum / n / rmean : 0.0};
    }
  } // namespace

  template <int dim>
  RegionGroups carve_region(dem::Model<dim> &m, const RegionParams &p, double inner,
                            RegionGroups G, std::ostream *progress)
  {
    using LN                = dem::LinearLaw<dim>;
    dem::MaterialParams mat = *p.material;
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
    dem::Random        rng(mat.seed);
    dem::Specimen<dim> packed =
        dem::pack_specimen<dim>(mat, v, rng, progress, "DEM region (material genesis)");
    std::tie(G.max_overlap_ratio, G.mean_overlap_ratio) = overlap_ratios(packed.model);
    G.genesis_steps                                     = packed.packing_steps;

    // Carve: the grains whose centres lie inside the ring, each shrunk by
    // its largest overlap with the region's walls (the ring; 3D also the
    // slab walls) so that no grain-wall contact carries force at the start
    // (fistPkg §4.2.2 moves a vessel's walls instead; the ring is the
    // continuum's boundary and cannot move). A grain more than half outside
    // would shrink below half its size: it is left out instead.
    const auto         &Q     = packed.model.particles;
    auto               &W     = m.walls;
    std::size_t         n_cut = 0, n_shrunk = 0;
    std::vector<double> shrunk; // radius each carved grain lost (finalization)
    const double        ring_tol = 1e-12 * inner;
    for (std::size_t i = 0; i < Q.size(); ++i)
      {
        dem::Vec<dim> x = Q.x[i];
        if constexpr (dim == 3)
          x[2] += 0.5 * t; // the vessel is centred at z = 0, the slab at t/2
        const double rho_xy = x.template head<2>().norm();
        if (rho_xy >= inner)
          continue;
        double gap = HUGE_VAL; // smallest grain-wall gap
        if (rho_xy + Q.radius[i] > inner - ring_tol)
          for (std::size_t f = 0; f < W.n_facets(); ++f)
            if (dim == 2 || (W.facet_wall[f] != G.slab_walls[0] &&
                             W.facet_wall[f] != G.slab_walls[1]))
              {
                std::array<double, dim> w;
                gap = std::min(gap, (W.closest_point(f, x, w) - x).norm() - Q.radius[i]);
              }
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
        const double rho = Q.mass[i] / ball_volume<dim>(Q.radius[i]);
        m.particles.add(x, r, rho);
        shrunk.push_back(Q.radius[i] - r);
      }
    if (progress)
      *progress << "DEM region: " << m.particles.size() << " of " << Q.size()
                << " packed grains carved (" << n_shrunk << " shrunk onto the ring, "
                << n_cut << " more than half outside left out)\n";

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
    dem::finalize_specimen(reg, rng, progress, false, shrunk);
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
      solid += ball_volume<dim>(r);
    const double volume = M_PI * inner * inner * t;
    G.porosity          = 1 - solid / volume;
    G.packed_porosity   = packed.porosity();
    m                   = std::move(rm);
    if (progress)
      *progress << "DEM region: " << G.n_bonds << " bonds, " << G.n_rattlers
                << " rattlers removed, porosity " << G.porosity << " (packing "
                << G.packed_porosity << ")\n";
    return G;
  }

  template RegionGroups carve_region<2>(dem::Model<2> &, const RegionParams &, double,
                                        RegionGroups, std::ostream *);
  template RegionGroups carve_region<3>(dem::Model<3> &, const RegionParams &, double,
                                        RegionGroups, std::ostream *);
} // namespace demfem::coupling
