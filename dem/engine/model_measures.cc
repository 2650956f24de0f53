// Measures of a Model's state (energies, unbalanced force, cracks) and the
// energy-balance check of the explicit integration (docs/architecture.md,
// "The DEM engine"); split from model.cc, which keeps the step itself.
#include "dem/engine/model.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace demfem::dem
{
  template <int dim>
  void Model<dim>::check_energy_balance()
  {
    double se = 0;
    for (const auto &g : groups_)
      se += g->total_strain_energy();
    // Only free degrees of freedom belong to the balance: the motion of fixed
    // ones is imposed from outside and enters through the boundary work.
    double      ke = 0;
    const auto &P  = particles;
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        if (!(P.fixity[i] & fix_translation))
          ke += 0.5 * P.mass[i] * P.v[i].squaredNorm();
        if (!(P.fixity[i] & fix_rotation))
          ke += 0.5 * P.inertia[i] * P.w[i].squaredNorm();
      }
    const double e = ke + se;
    if (!baseline_valid_)
      {
        energy0_        = e;
        work_in_        = 0;
        baseline_valid_ = true;
        return;
      }
    // Damping and slip only remove energy, so kinetic + strain energy cannot
    // exceed the initial energy plus the work put in, up to the factor of
    // common/growth_monitor.h (plus a tiny absolute floor).
    const double budget = std::max(energy0_ + work_in_, 0.0);
    if (e > instability::energy_balance_factor * budget + 1e-12 * (1 + budget))
      {
        std::ostringstream msg;
        msg << "energy balance violated at step " << step_ << ": kinetic + strain energy "
            << e << " J exceeds the initial energy plus external work " << budget
            << " J. The explicit integration is unstable: time step " << dt_
            << " s, critical estimate " << critical_timestep()
            << " s; likely causes: time step above critical, a stiffness contrast, or "
               "overlaps created without resetting the energy baseline.";
        throw InstabilityError(msg.str());
      }
  }

  template <int dim>
  double Model<dim>::kinetic_energy() const
  {
    double            e = 0;
    const std::size_t N = particles.size();
#pragma omp parallel for reduction(+ : e) schedule(static) if (N > parallel_threshold)
    for (std::size_t i = 0; i < N; ++i)
      e += 0.5 * (particles.mass[i] * particles.v[i].squaredNorm() +
                  particles.inertia[i] * particles.w[i].squaredNorm());
    return e;
  }

  template <int dim>
  double Model<dim>::strain_energy() const
  {
    double e = 0;
    for (const auto &g : groups_)
      for (std::size_t k = 0; k < g->size(); ++k)
        e += g->strain_energy(k);
    return e;
  }

  template <int dim>
  double Model<dim>::slip_energy() const
  {
    double e = 0;
    for (const auto &g : groups_)
      for (std::size_t k = 0; k < g->size(); ++k)
        e += g->slip_energy(k);
    return e;
  }

  template <int dim>
  double Model<dim>::unbalanced_ratio() const
  {
    double      unb = 0, con = 0;
    std::size_t nf = 0, nc = 0;
    for (std::size_t i = 0; i < particles.size(); ++i)
      if (!(particles.fixity[i] & fix_translation))
        {
          unb +=
              (particles.f[i] + particles.f_ext[i] + particles.mass[i] * gravity).norm();
          ++nf;
        }
    for (const auto &g : groups_)
      for (std::size_t k = 0; k < g->size(); ++k)
        if (g->force[k].squaredNorm() > 0)
          {
            con += g->force[k].norm();
            ++nc;
          }
    if (nf == 0 || nc == 0 || con == 0)
      return 0;
    return (unb / nf) / (con / nc);
  }

  template <int dim>
  std::vector<CrackRecord<dim>> Model<dim>::current_cracks() const
  {
    std::vector<CrackRecord<dim>> out = cracks;
    if (out.empty())
      return out;
    std::unordered_map<std::int64_t, std::uint32_t> where;
    where.reserve(particles.size());
    for (std::size_t i = 0; i < particles.size(); ++i)
      where.emplace(particles.id[i], static_cast<std::uint32_t>(i));
    for (auto &c : out)
      {
        const auto a = where.find(c.id1);
        if (a == where.end())
          continue;
        const std::uint32_t i  = a->second;
        const double        R1 = particles.radius[i];
        Vec<dim>            d;
        double              R2 = 0;
        if (c.id2 < 0)
          {
            const std::size_t facet = static_cast<std::size_t>(-1 - c.id2);
            if (facet >= walls.n_facets())
              continue;
            std::array<double, dim> wgt;
            d = walls.closest_point(facet, particles.x[i], wgt) - particles.x[i];
          }
        else
          {
            const auto b = where.find(c.id2);
            if (b == where.end())
              continue;
            d  = particles.x[b->second] - particles.x[i];
            R2 = particles.radius[b->second];
          }
        const double dist = d.norm();
        if (!(dist > 0))
          continue;
        const Vec<dim> n   = d / dist;
        const double   gap = dist - R1 - R2;
        if (c.type == BondType::smooth_joint)
          {
            // The joint plane is fixed in space (seed 001): the crack keeps
            // its normal and sits at the current contact location.
            c.position = particles.x[i] + (R1 + 0.5 * gap) * n;
            c.gap      = c.gap_break + (gap - c.contact_gap_break);
            continue;
          }
        // Minimal rotation taking the old normal to the new one.
        Vec<dim> off = c.offset;
        if constexpr (dim == 2)
          {
            const double ang = std::atan2(cross2(c.normal, n), c.normal.dot(n));
            const double cs = std::cos(ang), sn = std::sin(ang);
            off = Vec<2>(cs * c.offset[0] - sn * c.offset[1],
                         sn * c.offset[0] + cs * c.offset[1]);
          }
        else
          {
            const Vec<3> axis = c.normal.cross(n);
            const double sn = axis.norm(), cs = c.normal.dot(n);
            if (sn > 1e-15)
              off = Eigen::AngleAxisd(std::atan2(sn, cs), axis / sn) * c.offset;
          }
        c.offset   = off;
        c.normal   = n;
        c.position = particles.x[i] + (R1 + 0.5 * gap) * n + off;
        c.gap      = c.gap_break + (gap - c.contact_gap_break);
      }
    return out;
  }

  // The members defined here (model.cc instantiates the class).
  template void                        Model<2>::check_energy_balance();
  template double                      Model<2>::kinetic_energy() const;
  template double                      Model<2>::strain_energy() const;
  template double                      Model<2>::slip_energy() const;
  template double                      Model<2>::unbalanced_ratio() const;
  template std::vector<CrackRecord<2>> Model<2>::current_cracks() const;
  template void                        Model<3>::check_energy_balance();
  template double                      Model<3>::kinetic_energy() const;
  template double                      Model<3>::strain_energy() const;
  template double                      Model<3>::slip_energy() const;
  template double                      Model<3>::unbalanced_ratio() const;
  template std::vector<CrackRecord<3>> Model<3>::current_cracks() const;
} // namespace demfem::dem
