#pragma once
// Excavation and damage bookkeeping shared by the embedded tunnel
// (coupling/tunnel_run.cc) and the full-DEM reference
// (coupling/full_dem_reference.cc), so that both models are measured the
// same way (issue 6: the embedded model is compared with the reference on
// these numbers). Plain DEM: no deal.II.
//
// * Excavation (issue 5, workflow step 3): the grains whose centres lie
//   inside the tunnel radius are removed; the forces they exerted on the
//   remaining grains are returned by particle id so that they can be applied
//   and relaxed to zero over the stages.
// * Damage-zone depth: largest distance from the tunnel wall of a crack
//   formed from the excavation on (isolated cracks of the in-situ loading
//   are not excavation damage).
// * Wall convergence: mean inward radial displacement, since the excavation,
//   of the grains whose reference centre lies within one mean diameter of
//   the wall.
#include "dem/model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace demfem::coupling::excavation
{
  /// State kept from the excavation on: positions by particle id at the
  /// excavation, forces the removed grains exerted on the remaining ones (by
  /// id), and the crack count before it.
  struct Record
  {
    std::vector<dem::Vec<2>> ref;
    std::vector<dem::Vec<2>> removed_forces;
    std::size_t              cracks_before = 0;
    std::size_t              n_removed     = 0;
  };

  /// Removes the grains with |x| < a (tunnel centred at the origin) and
  /// returns the record; the energy baseline is restarted (the model was
  /// changed by hand).
  inline Record remove_tunnel_grains(dem::Model<2> &m, double a)
  {
    Record r;
    auto  &P = m.particles;
    r.ref.assign(P.size() ? *std::max_element(P.id.begin(), P.id.end()) + 1 : 0,
                 dem::Vec<2>::Zero());
    for (std::size_t i = 0; i < P.size(); ++i)
      r.ref[P.id[i]] = P.x[i];
    std::vector<char> rm(P.size(), 0);
    for (std::size_t i = 0; i < P.size(); ++i)
      r.n_removed += (rm[i] = P.x[i].norm() < a);
    r.removed_forces.assign(r.ref.size(), dem::Vec<2>::Zero());
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (!grp.is_wall[k])
            {
              // grp.force is the force on end2 (minus that on end1)
              const auto i = grp.end1[k], j = grp.end2[k];
              if (rm[i] && !rm[j])
                r.removed_forces[P.id[j]] += grp.force[k];
              else if (rm[j] && !rm[i])
                r.removed_forces[P.id[i]] -= grp.force[k];
            }
      }
    m.remove_particles(rm);
    m.reset_energy_baseline();
    r.cracks_before = m.cracks.size();
    return r;
  }

  /// Applies the fraction `remaining` of the removed grains' forces as
  /// external forces (staged excavation: relaxed to zero over the stages).
  inline void apply_removed_forces(dem::Model<2> &m, const Record &r, double remaining)
  {
    auto &P = m.particles;
    for (std::size_t i = 0; i < P.size(); ++i)
      P.f_ext[i] = remaining * r.removed_forces[P.id[i]];
  }

  /// Cracks of mode `mode` (0 tension, 1 shear; < 0 all) with index >= from.
  inline std::size_t count_cracks(const dem::Model<2> &m, int mode, std::size_t from = 0)
  {
    std::size_t n = 0;
    for (std::size_t k = from; k < m.cracks.size(); ++k)
      n += (mode < 0 || m.cracks[k].mode == mode);
    return n;
  }

  /// Largest distance from the wall r = a of the cracks with index >= from
  /// and centre distance <= r_max.
  inline double damage_zone_depth(const dem::Model<2> &m, std::size_t from, double a,
                                  double r_max = HUGE_VAL)
  {
    double d = 0;
    for (std::size_t k = from; k < m.cracks.size(); ++k)
      if (m.cracks[k].position.norm() <= r_max)
        d = std::max(d, m.cracks[k].position.norm() - a);
    return d;
  }

  /// Cracks (all, since the start) at a distance > r from the centre: near
  /// an outer boundary (coupling ring or servo membrane) when r is that
  /// boundary's radius less two grain diameters.
  inline std::size_t cracks_beyond(const dem::Model<2> &m, double r)
  {
    std::size_t n = 0;
    for (const auto &c : m.cracks)
      n += c.position.norm() > r;
    return n;
  }

  /// Mean inward radial displacement of the grains whose reference centre
  /// lies within d of the wall r = a (their count in n; rows x, y, ux, uy).
  inline double wall_convergence(const dem::Model<2>            &m,
                                 const std::vector<dem::Vec<2>> &ref, double a, double d,
                                 std::size_t                        *n    = nullptr,
                                 std::vector<std::array<double, 4>> *rows = nullptr)
  {
    const auto &P = m.particles;
    double      s = 0;
    std::size_t c = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        if (std::size_t(P.id[i]) >= ref.size())
          continue;
        const dem::Vec<2> &X = ref[P.id[i]];
        const double       r = X.norm();
        if (r < a + d)
          {
            const dem::Vec<2> u = P.x[i] - X;
            s -= u.dot(X / r);
            ++c;
            if (rows)
              rows->push_back({X[0], X[1], u[0], u[1]});
          }
      }
    if (n)
      *n = c;
    return c ? s / c : 0.0;
  }
} // namespace demfem::coupling::excavation
