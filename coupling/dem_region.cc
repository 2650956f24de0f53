#include "coupling/dem_region.h"

#include "dem/measure/measurement.h"
#include "dem/specimen/memory_budget.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace demfem::coupling
{
  using dem::Vec;

  void RegionParams::validate(const std::string &w, int dim) const
  {
    const double inf = HUGE_VAL;
    dem::check_range(w, "DEM region/radius", radius, 0, inf, true);
    dem::check_range(w, "DEM region/grain diameter (smallest)", d_lo, 0, inf, true);
    dem::check_range(w, "DEM region/grain diameter (largest)", d_hi, d_lo, inf);
    dem::check_range(w, "DEM region/density", density, 0, inf, true);
    dem::check_range(w, "DEM region/material pressure", material_pressure, 0, inf);
    dem::check_range(w, "DEM region/local damping", damping, 0, 1, false, true);
    dem::check_range(w, "DEM region/lnm emod", lnm_emod, 0, inf, true);
    dem::check_range(w, "DEM region/lnm krat", lnm_krat, 0, inf, true);
    dem::check_range(w, "DEM region/lnm fric", lnm_fric, 0, inf);
    dem::check_range(w, "DEM region/emod", emod, 0, inf, true);
    dem::check_range(w, "DEM region/krat", krat, 0, inf, true);
    dem::check_range(w, "DEM region/fric", fric, 0, inf);
    dem::check_range(w, "DEM region/igap", igap, 0, inf);
    dem::check_range(w, "DEM region/fj Nr", fj_Nr, 1, 64);
    dem::check_range(w, "DEM region/fj ten", fj_ten, 0, inf);
    dem::check_range(w, "DEM region/fj coh", fj_coh, 0, inf);
    dem::check_range(w, "DEM region/fj fa", fj_fa, 0, 90, false, true);
    if (d_hi > 0.25 * radius)
      throw dem::InputError(w + ": DEM region/grain diameter " + std::to_string(d_hi) +
                            " m is too large for the region radius " +
                            std::to_string(radius) + " m (allowed: <= radius/4)");
    // Grains the genesis packs (the square box around the region that the
    // region is carved from, region_genesis.cc: side 2 (b + 2 d_hi); 2D per
    // unit thickness, 3D the slab's), estimated before anything is
    // allocated at the porosity the genesis reaches (about 0.16 in 2D, 0.40
    // for spheres between walls).
    const double d    = mean_diameter();
    const double side = 2 * (radius + 2 * d_hi);
    const double Vr   = side * side * (dim == 3 ? slab_thickness : 1.0);
    const double Vg   = dim == 2 ? M_PI * d * d / 4 : M_PI * d * d * d / 6;
    dem::check_memory((dim == 3 ? 0.60 : 0.84) * Vr / Vg, dim, memory_limit, w,
                      "DEM region/grain diameter (or the material file's sizes)",
                      "DEM region/memory limit");
    if (dim == 3)
      {
        dem::check_range(w, "DEM region/fj_Nal", fj_Nal, 3, 64);
        // At least two of the largest grains through the slab, so that the
        // slab is a granular layer and not a monolayer between the walls.
        // Checked in the key's unit, mean grain diameters (tunnel_prm.cc).
        dem::check_range(w, "DEM region/slab thickness", slab_thickness / d, 2 * d_hi / d,
                         4 * radius / d);
      }
  }

  dem::MaterialParams RegionParams::keys_material() const
  {
    dem::MaterialParams m;
    m.type = "flatjointed";
    dem::SizePiece piece;
    piece.d_lo      = d_lo;
    piece.d_hi      = d_hi;
    m.sizes         = {piece};
    m.density       = density;
    m.local_damping = damping;
    m.seed          = seed;
    m.lnm_emod      = lnm_emod;
    m.lnm_krat      = lnm_krat;
    m.lnm_fric      = lnm_fric;
    m.emod          = emod;
    m.krat          = krat;
    m.fric          = fric;
    m.igap          = igap;
    m.fj_B          = 1; // every joint bonded
    m.fj_G          = 0;
    m.fj_Nr         = fj_Nr;
    m.fj_Nal        = fj_Nal;
    // Unbreakable (verification): strengths no load of the tests reaches.
    const double huge = 1e30;
    m.fj_ten          = {breakable ? fj_ten : huge, 0};
    m.fj_coh          = {breakable ? fj_coh : huge, 0};
    m.fj_fa           = fj_fa;
    m.Pm              = material_pressure > 0 ? material_pressure : lnm_emod / 800;
    m.memory_limit    = memory_limit;
    return m;
  }

  double RegionParams::crossing_time() const
  {
    const dem::MaterialParams m = genesis_material();
    return 2 * radius / std::sqrt(m.emod / m.density);
  }

  std::int64_t ramp_steps(double duration, double dt)
  {
    // The ramp's model time is steps x dt; a relative 1e-12 absorbs the
    // round-off of duration / dt when the duration is a whole number of steps.
    const double n = std::ceil(duration / dt * (1 - 1e-12));
    return std::max<std::int64_t>(1, static_cast<std::int64_t>(n));
  }

  namespace
  {
    // Distance from the origin to the segment [a, b] (2D points).
    double segment_distance(const Eigen::Vector2d &a, const Eigen::Vector2d &b)
    {
      const Eigen::Vector2d d  = b - a;
      const double          dd = d.squaredNorm();
      const double          t  = dd > 0 ? std::clamp(-a.dot(d) / dd, 0.0, 1.0) : 0.0;
      return (a + t * d).norm();
    }

    // 3D: radius of the largest cylinder about z inside the lateral facets
    // (their edges projected on the xy plane: chords, or points for
    // vertical edges); checks that the facets span 0 <= z <= t.
    double inscribed_radius_3d(const dem::Walls<3> &W, double b, double t)
    {
      double inner = b, zlo = HUGE_VAL, zhi = -HUGE_VAL;
      for (const auto &f : W.facet)
        for (int a = 0; a < 3; ++a)
          {
            const Vec<3> &p = W.vertex[f[a]], &q = W.vertex[f[(a + 1) % 3]];
            inner = std::min(inner, segment_distance(p.head<2>(), q.head<2>()));
            zlo   = std::min(zlo, p[2]);
            zhi   = std::max(zhi, p[2]);
          }
      const double tol = 1e-9 * std::max(b, t);
      if (std::abs(zlo) > tol || std::abs(zhi - t) > tol)
        throw dem::InputError(
            "DEM region: the lateral wall facets span z = " + std::to_string(zlo) +
            " .. " + std::to_string(zhi) + " m, not the slab 0 .. " + std::to_string(t) +
            " m (DEM region/slab thickness)");
      return inner;
    }

  } // namespace

  int add_cylinder_ring(dem::Walls<3> &W, double radius, double thickness,
                        unsigned int n_around, unsigned int n_layers,
                        const std::string &name)
  {
    if (n_around < 3 || n_layers < 1 || !(radius > 0) || !(thickness > 0))
      throw dem::InputError("add_cylinder_ring: needs radius > 0, thickness > 0, at "
                            "least 3 facets around and 1 layer");
    const int        wall = W.add_wall(name);
    std::vector<int> v((n_layers + 1) * n_around);
    for (unsigned int l = 0; l <= n_layers; ++l)
      for (unsigned int k = 0; k < n_around; ++k)
        {
          const double th     = 2 * M_PI * k / n_around;
          v[l * n_around + k] = W.add_vertex(Vec<3>(
              radius * std::cos(th), radius * std::sin(th), thickness * l / n_layers));
        }
    for (unsigned int l = 0; l < n_layers; ++l)
      for (unsigned int k = 0; k < n_around; ++k)
        {
          const unsigned int k1 = (k + 1) % n_around;
          const int          a = v[l * n_around + k], b = v[l * n_around + k1],
                    c = v[(l + 1) * n_around + k1], d = v[(l + 1) * n_around + k];
          W.add_facet(wall, {{a, b, c}});
          W.add_facet(wall, {{a, c, d}});
        }
    return wall;
  }

  // The carving leaves the rim's grains 1e-7 of their gap off the ring
  // (coupling/region_genesis.cc): the ring contacts close under the first
  // load, so the critical time step counts them from the start
  // (Model::touching_gap). Set for every region, where it is built.
  namespace
  {
    template <int dim>
    void count_touching_contacts(dem::Model<dim> &m)
    {
      m.touching_gap = 1e-6 * m.particles.min_radius();
    }
  } // namespace

  template <int dim>
  RegionGroups build_region(dem::Model<dim> &m, const RegionParams &p,
                            std::ostream *progress)
  {
    p.validate("DEM region", dim);
    auto        &W = m.walls;
    const double t = dim == 3 ? p.slab_thickness : 1.0; // 2D: unit thickness
    if (W.n_facets() < 8)
      throw std::runtime_error(
          "build_disk_region: the model needs the ring of wall facets");
    // Largest circle inside the ring polygon (chords lie inside the circle).
    double inner = p.radius;
    if constexpr (dim == 2)
      for (const auto &f : W.facet)
        inner = std::min(inner, 0.5 * (W.vertex[f[0]] + W.vertex[f[1]]).norm());
    else
      inner = inscribed_radius_3d(W, p.radius, t);

    RegionGroups G;
    if constexpr (dim == 3)
      {
        // The slab walls: one triangle per plane, containing the ring's
        // cross-section (x + y <= 2 e holds on the disk of radius e / 1.05).
        // One facet, not two: the engine gives a grain near an edge shared by
        // two coplanar facets a second contact on the edge, with a tilted
        // normal (an in-plane force on a frictionless wall).
        double reach = 0;
        for (const auto &x : W.vertex)
          reach = std::max(reach, 1.05 * x.template head<2>().norm());
        for (int s = 0; s < 2; ++s)
          {
            const double z  = s * t;
            const int    w  = W.add_wall(s == 0 ? "slab wall z=0" : "slab wall z=t");
            const int    v0 = W.add_vertex(Vec<3>(-2 * reach, -2 * reach, z)),
                      v1    = W.add_vertex(Vec<3>(4 * reach, -2 * reach, z)),
                      v2    = W.add_vertex(Vec<3>(-2 * reach, 4 * reach, z));
            W.add_facet(w, {{v0, v1, v2}});
            G.slab_walls[s] = w;
          }
      }
    RegionGroups carved = carve_region<dim>(m, p, inner, G, progress);
    count_touching_contacts(m);
    return carved;
  }

  template RegionGroups build_region<2>(dem::Model<2> &, const RegionParams &,
                                        std::ostream *);
  template RegionGroups build_region<3>(dem::Model<3> &, const RegionParams &,
                                        std::ostream *);

  Eigen::Matrix2d region_stress(const dem::Model<2> &m, const Vec<2> &c, double r)
  {
    Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (!grp.is_wall[k] && (grp.xc[k] - c).norm() < r)
            {
              const Vec<2> l = m.particles.x[grp.end2[k]] - m.particles.x[grp.end1[k]];
              s -= grp.force[k] * l.transpose();
            }
      }
    s /= M_PI * r * r;
    return 0.5 * (s + s.transpose());
  }

  namespace
  {
    // Love-Weber sum over the contacts whose contact point lies in the
    // cylinder |(x - c)_xy| < r, z0 <= z <= z1, divided by `volume`.
    Eigen::Matrix3d love_weber_3d(const dem::Model<3> &m, const Vec<3> &c, double r,
                                  double z0, double z1, double volume)
    {
      // sigma = (1/V) sum over the grains p of sum over their contacts of
      // (x_c - x_p) f_p^T (f_p the force on p; tension positive). A
      // grain-grain contact (force[k] on end 2, -force[k] on end 1) gives
      // -force[k] (x2 - x1)^T; a grain-wall contact (force[k] on the wall)
      // gives -force[k] (x_c - x1)^T, x_c the contact location (within half
      // the overlap of the wall surface). Transposes do not matter: the
      // result is symmetrized.
      Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
      for (int g = 0; g < m.n_groups(); ++g)
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            if ((grp.xc[k] - c).head<2>().norm() < r && grp.xc[k][2] >= z0 &&
                grp.xc[k][2] <= z1)
              {
                const Vec<3> l =
                    grp.is_wall[k]
                        ? Vec<3>(grp.xc[k] - m.particles.x[grp.end1[k]])
                        : Vec<3>(m.particles.x[grp.end2[k]] - m.particles.x[grp.end1[k]]);
                s -= grp.force[k] * l.transpose();
              }
        }
      s /= volume;
      return 0.5 * (s + s.transpose());
    }
  } // namespace

  Eigen::Matrix3d region_stress(const dem::Model<3> &m, const Vec<3> &c, double r,
                                double thickness)
  {
    return love_weber_3d(m, c, r, -HUGE_VAL, HUGE_VAL, M_PI * r * r * thickness);
  }

  Eigen::Matrix3d region_stress(const dem::Model<3> &m, const Vec<3> &c, double r,
                                double z0, double z1)
  {
    return love_weber_3d(m, c, r, z0, z1, M_PI * r * r * (z1 - z0));
  }
} // namespace demfem::coupling
