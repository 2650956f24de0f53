// Measurement (fistPkg §5.1, Table 8; §3.1).
#include "dem/measure/measurement.h"

#include "dem/laws/contact_bond_law.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/parallel_bond_law.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace demfem::dem
{
  namespace
  {
    /// Area (2D) or volume (3D) of the intersection of two disks or balls of
    /// radii a and b whose centres are d apart (circle-circle lens area;
    /// sphere-sphere lens volume pi (a + b - d)^2 (d^2 + 2 d (a + b) -
    /// 3 (a - b)^2) / (12 d)).
    template <int dim>
    double lens(double a, double b, double d)
    {
      if (d >= a + b)
        return 0;
      if (d <= std::abs(a - b))
        return ball_volume<dim>(std::min(a, b));
      if constexpr (dim == 2)
        {
          const double ca = std::clamp((d * d + a * a - b * b) / (2 * d * a), -1.0, 1.0);
          const double cb = std::clamp((d * d + b * b - a * a) / (2 * d * b), -1.0, 1.0);
          const double k =
              std::max(0.0, (-d + a + b) * (d + a - b) * (d - a + b) * (d + a + b));
          return a * a * std::acos(ca) + b * b * std::acos(cb) - 0.5 * std::sqrt(k);
        }
      else
        {
          const double h = a + b - d;
          return M_PI * h * h * (d * d + 2 * d * (a + b) - 3 * (a - b) * (a - b)) /
                 (12 * d);
        }
    }

    template <int dim>
    bool inside(const Region<dim> &r, const Vec<dim> &x)
    {
      return (x - r.center).squaredNorm() <= r.radius * r.radius;
    }

    // sum_c F (x) l over active contacts accepted by `take(xc)`.
    template <int dim, class Take>
    Tensor<dim> force_branch_sum(const Model<dim> &m, bool include_walls, Take take)
    {
      Tensor<dim> S = Tensor<dim>::Zero();
      for (int g = 0; g < m.n_groups(); ++g)
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            {
              const bool wall = grp.is_wall[k];
              if ((wall && !include_walls) || !take(grp.xc[k]))
                continue;
              const Vec<dim> &F = grp.force[k];
              if (F.squaredNorm() == 0)
                continue;
              const Vec<dim> x1 = m.particles.x[grp.end1[k]];
              // Branch vector: centre to centre; ball-wall: centre to contact.
              const Vec<dim> l = (wall ? grp.xc[k] : m.particles.x[grp.end2[k]]) - x1;
              S += F * l.transpose();
            }
        }
      return S;
    }
  } // namespace

  template <int dim>
  Tensor<dim> region_stress(const Model<dim> &m, const Region<dim> &r, bool include_walls)
  {
    // Contacts located in the region (PFC: sigma = -(1/V) sum_Nc F (x) L);
    // measured closer to the wall stress than the grain-centre (Love-Weber)
    // variant in the elastic UCS of lab_tests_test (+8.5 % vs +10.2 %).
    const Tensor<dim> S = force_branch_sum(
        m, include_walls, [&](const Vec<dim> &x) { return inside(r, x); });
    const Tensor<dim> s = -S / r.volume();
    return 0.5 * (s + s.transpose());
  }

  template <int dim>
  Tensor<dim> assembly_stress(const Model<dim> &m, double V, bool include_walls)
  {
    const Tensor<dim> S =
        force_branch_sum(m, include_walls, [](const Vec<dim> &) { return true; });
    const Tensor<dim> s = -S / V;
    return 0.5 * (s + s.transpose());
  }

  template <int dim>
  Tensor<dim> gauge_strain(const Model<dim> &m, const std::vector<std::uint32_t> &set)
  {
    // Least squares x = A X + c over the set: centre both, then
    // A = (sum x' X'^T)(sum X' X'^T)^-1; strain = sym(A) - I.
    const auto &P = m.particles;
    if (set.size() < static_cast<std::size_t>(dim + 1))
      throw InputError("gauge_strain: the gauge needs at least dim + 1 grains");
    Vec<dim> X0 = Vec<dim>::Zero(), x0 = Vec<dim>::Zero();
    for (auto i : set)
      {
        X0 += P.x0[i];
        x0 += P.x[i];
      }
    X0 /= set.size();
    x0 /= set.size();
    Tensor<dim> B = Tensor<dim>::Zero(), C = Tensor<dim>::Zero();
    for (auto i : set)
      {
        const Vec<dim> X = P.x0[i] - X0, x = P.x[i] - x0;
        B += x * X.transpose();
        C += X * X.transpose();
      }
    const Tensor<dim> A = B * C.inverse();
    return 0.5 * (A + A.transpose()) - Tensor<dim>::Identity();
  }

  template <int dim>
  std::vector<std::uint32_t> grains_in(const Model<dim> &m, const Region<dim> &r)
  {
    std::vector<std::uint32_t> s;
    for (std::size_t i = 0; i < m.particles.size(); ++i)
      if (inside(r, m.particles.x[i]))
        s.push_back(static_cast<std::uint32_t>(i));
    return s;
  }

  template <int dim>
  double porosity(const Model<dim> &m, double V)
  {
    double Vg = 0;
    for (double r : m.particles.radius)
      Vg += ball_volume<dim>(r);
    return 1 - Vg / V;
  }

  namespace
  {
    // Summed lens volume of the overlapping grain pairs whose contact point
    // satisfies `in` (the porosities count each overlap once).
    template <int dim, class In>
    double overlap_volume(const Model<dim> &m, In &&in)
    {
      const auto &P = m.particles;
      double      V = 0;
      for (int g = 0; g < m.n_groups(); ++g)
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            {
              if (grp.is_wall[k] || !in(grp.xc[k]))
                continue;
              const auto   i = grp.end1[k], j = grp.end2[k];
              const double d = (P.x[i] - P.x[j]).norm();
              if (d < P.radius[i] + P.radius[j])
                V += lens<dim>(P.radius[i], P.radius[j], d);
            }
        }
      return V;
    }
  } // namespace

  template <int dim>
  double region_porosity(const Model<dim> &m, const Region<dim> &r)
  {
    // Measurement-based porosity (fistPkg §5.1): the part of each grain that
    // lies inside the region (exact disk/ball lens with the region), less the
    // grain-grain overlaps whose contact point is in the region, so that the
    // value does not jump by a whole grain when a centre crosses the rim (a
    // centre count scatters by about 1/sqrt(grains in the region)).
    const auto &P  = m.particles;
    double      Vg = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      Vg += lens<dim>(P.radius[i], r.radius, (P.x[i] - r.center).norm());
    Vg -= overlap_volume(m, [&](const Vec<dim> &xc) { return inside(r, xc); });
    return 1 - Vg / r.volume();
  }

  template <int dim>
  double column_porosity(const Model<dim> &m, double radius, double height)
  {
    if constexpr (dim == 2)
      return region_porosity(m, Region<2>{Vec<2>::Zero(), radius});
    else
      {
        // A sphere's part inside the cylinder: its z slices (disks of
        // radius r cos(theta) at z = r sin(theta)) cut by the circle of the
        // cylinder, integrated over theta (smooth in theta: the midpoint
        // rule's error falls fast; 48 points resolve the lens of a grain
        // crossing the rim to about 1e-4 of its volume).
        constexpr int n  = 48;
        const auto   &P  = m.particles;
        double        Vg = 0;
        for (std::size_t i = 0; i < P.size(); ++i)
          {
            const double r = P.radius[i], rho = P.x[i].template head<2>().norm();
            if (rho + r <= radius)
              Vg += ball_volume<3>(r);
            else if (rho - r < radius)
              for (int k = 0; k < n; ++k)
                {
                  const double th = M_PI * ((k + 0.5) / n - 0.5);
                  Vg += lens<2>(r * std::cos(th), radius, rho) * r * std::cos(th) * M_PI /
                        n;
                }
          }
        Vg -= overlap_volume(
            m, [&](const Vec<3> &xc) { return xc.template head<2>().norm() <= radius; });
        return 1 - Vg / (M_PI * radius * radius * height);
      }
  }

  template <int dim>
  ContactCounts contact_counts(const Model<dim> &m)
  {
    ContactCounts c;
    c.grains = m.particles.size();
    using FJ = FlatJointLaw<dim>;
    using PB = ParallelBondLaw<dim>;
    using CB = ContactBondLaw<dim>;
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp  = m.group(g);
        const char *name = grp.law_name();
        for (std::size_t k = 0; k < grp.size(); ++k)
          {
            if (grp.active(k))
              (grp.is_wall[k] ? c.active_grain_wall : c.active_grain_grain)++;
            if (grp.is_wall[k])
              continue;
            if (std::strcmp(name, FJ::name) == 0)
              {
                const auto   &fg = static_cast<const ContactGroup<dim, FJ> &>(grp);
                const double *st = grp.state(k);
                const int     ne = FJ::element_count(fg.params);
                const int     nb = FJ::bonded_count(fg.params, st);
                ++c.fj;
                c.fj_elements += ne;
                c.fj_bonded_elements += nb;
                if (nb > 0)
                  ++c.bonds;
                if (nb == ne)
                  ++c.fj_bonded;
                else if (nb == 0 && FJ::surface_gap(st) > 0)
                  ++c.fj_gapped;
                else if (nb == 0)
                  ++c.fj_slit;
              }
            else if (std::strcmp(name, PB::name) == 0)
              c.bonds += PB::bonded(grp.state(k)) ? 1 : 0;
            else if (std::strcmp(name, CB::name) == 0)
              c.bonds += CB::bonded(grp.state(k)) ? 1 : 0;
          }
      }
    if (c.grains > 0)
      {
        c.coordination      = 2.0 * c.active_grain_grain / c.grains;
        c.bond_coordination = 2.0 * c.bonds / c.grains;
      }
    return c;
  }

  template <int dim>
  Tensor<dim> fabric_tensor(const Model<dim> &m, const Region<dim> *region)
  {
    Tensor<dim> F = Tensor<dim>::Zero();
    std::size_t n = 0;
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          {
            if (grp.is_wall[k] || !grp.active(k) ||
                (region && !inside(*region, grp.xc[k])))
              continue;
            const Vec<dim> d = m.particles.x[grp.end2[k]] - m.particles.x[grp.end1[k]];
            const double   L = d.norm();
            if (L == 0)
              continue;
            F += d * d.transpose() / (L * L);
            ++n;
          }
      }
    return n ? Tensor<dim>(F / n) : F;
  }

  template <int dim>
  double max_contact_force(const Model<dim> &m)
  {
    double f = 0;
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          f = std::max(f, grp.force[k].norm());
      }
    return f;
  }

#define DEMFEM_INST(dim)                                                                 \
  template Tensor<dim> region_stress(const Model<dim> &, const Region<dim> &, bool);     \
  template Tensor<dim> assembly_stress(const Model<dim> &, double, bool);                \
  template Tensor<dim> gauge_strain(const Model<dim> &,                                  \
                                    const std::vector<std::uint32_t> &);                 \
  template std::vector<std::uint32_t> grains_in(const Model<dim> &,                      \
                                                const Region<dim> &);                    \
  template double                     porosity(const Model<dim> &, double);              \
  template double        region_porosity(const Model<dim> &, const Region<dim> &);       \
  template double        column_porosity(const Model<dim> &, double, double);            \
  template ContactCounts contact_counts(const Model<dim> &);                             \
  template Tensor<dim>   fabric_tensor(const Model<dim> &, const Region<dim> *);         \
  template double        max_contact_force(const Model<dim> &);
  DEMFEM_INST(2)
  DEMFEM_INST(3)
#undef DEMFEM_INST
} // namespace demfem::dem
