#pragma once
// Excavation and damage bookkeeping shared by the embedded tunnel
// (coupling/tunnel_run.cc) and the full-DEM reference
// (coupling/full_dem_reference.cc), so that both models are measured the
// same way (the study compares the embedded model with the reference on
// these numbers). Plain DEM: no deal.II.
//
// * Excavation (the third step of the tunnel workflow): the grains whose
//   centres lie inside the tunnel radius are removed; the forces they exerted
//   on the remaining grains are returned by particle id so that they can be
//   applied and relaxed to zero over the stages.
// * Damage-zone depth: the 90th percentile (nearest rank) of the distances
//   from the tunnel wall of the cracks formed from the excavation on
//   (isolated cracks of the in-situ loading are not excavation damage). The
//   largest distance is reported on its own: one stray crack decides it, so
//   it scatters between packings far more than the zone it bounds.
// * Wall convergence: mean inward radial displacement, since the excavation,
//   of the grains whose reference centre lies within one mean diameter of
//   the wall and that are still attached to the rock mass.
#include "coupling/damage_zone.h"
#include "dem/engine/model.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>

#include <vector>

namespace demfem::coupling::excavation
{
  /// State kept from the excavation on: positions by particle id at the
  /// excavation, forces the removed grains exerted on the remaining ones (by
  /// id), and the crack count before it.
  template <int dim>
  struct Record
  {
    std::vector<dem::Vec<dim>> ref;
    std::vector<dem::Vec<dim>> removed_forces;
    std::size_t                cracks_before = 0;
    std::size_t                n_removed     = 0;
  };

  /// Removes the grains with in-plane |(x, y)| < a (tunnel centred at the
  /// origin, along z in 3D) and returns the record; grains whose translation
  /// is prescribed (slaved to a continuum, e.g. a 3D section's end layers)
  /// stay: the continuum's own tunnel is excavated by releasing its wall
  /// traction. The energy baseline is restarted (the model was changed by
  /// hand).
  template <int dim>
  Record<dim> remove_tunnel_grains(dem::Model<dim> &m, double a)
  {
    Record<dim> r;
    auto       &P = m.particles;
    r.ref.assign(P.size() ? *std::max_element(P.id.begin(), P.id.end()) + 1 : 0,
                 dem::Vec<dim>::Zero());
    for (std::size_t i = 0; i < P.size(); ++i)
      r.ref[P.id[i]] = P.x[i];
    std::vector<char> rm(P.size(), 0);
    for (std::size_t i = 0; i < P.size(); ++i)
      r.n_removed += (rm[i] = P.x[i].template head<2>().norm() < a &&
                              !(P.fixity[i] & dem::fix_translation));
    r.removed_forces.assign(r.ref.size(), dem::Vec<dim>::Zero());
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
  template <int dim>
  void apply_removed_forces(dem::Model<dim> &m, const Record<dim> &r, double remaining)
  {
    auto &P = m.particles;
    for (std::size_t i = 0; i < P.size(); ++i)
      P.f_ext[i] = remaining * r.removed_forces[P.id[i]];
  }

  /// Cracks of mode `mode` (0 tension, 1 shear; < 0 all) with index >= from.
  template <int dim>
  std::size_t count_cracks(const dem::Model<dim> &m, int mode, std::size_t from = 0)
  {
    std::size_t n = 0;
    for (std::size_t k = from; k < m.cracks.size(); ++k)
      n += (mode < 0 || m.cracks[k].mode == mode);
    return n;
  }

  /// Cracks since the start by what broke, as a JSON object
  /// `{"flat_joint": n, ...}` (every bond type, zeros included).
  template <int dim>
  nlohmann::ordered_json cracks_by_type(const dem::Model<dim> &m)
  {
    std::array<std::size_t, dem::n_bond_types> n{};
    for (const auto &c : m.cracks)
      if (c.type != dem::BondType::none)
        ++n[static_cast<int>(c.type)];
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    for (int t = 0; t < dem::n_bond_types; ++t)
      j[dem::bond_type_name(static_cast<dem::BondType>(t))] = n[t];
    return j;
  }

  /// The members of cracks_by_type() as a JSON fragment without braces,
  /// `"contact_bond": 0, "parallel_bond": 0, ...` (for summaries still
  /// assembled as text).
  template <int dim>
  std::string cracks_by_type_json(const dem::Model<dim> &m)
  {
    const nlohmann::ordered_json all = cracks_by_type(m); // outlives the loop
    std::string                  s;
    for (const auto &[name, n] : all.items())
      s +=
          (s.empty() ? "" : ", ") + nlohmann::ordered_json(name).dump() + ": " + n.dump();
    return s;
  }

  /// Positions (z = 0 in 2D) of the cracks with index >= from and in-plane
  /// centre distance <= r_max.
  template <int dim>
  std::vector<std::array<double, 3>> crack_positions(const dem::Model<dim> &m,
                                                     std::size_t            from,
                                                     double r_max = HUGE_VAL)
  {
    std::vector<std::array<double, 3>> x;
    for (std::size_t k = from; k < m.cracks.size(); ++k)
      {
        const auto &p = m.cracks[k].position;
        if (p.template head<2>().norm() <= r_max)
          x.push_back({{p[0], p[1], dim == 3 ? p[dim - 1] : 0.0}});
      }
    return x;
  }

  /// The damage zone (coupling/damage_zone.h: the zone connected to the
  /// wall, its percentile depth, sector depths, notch, damaged area) of the
  /// cracks with index >= from and in-plane centre distance <= r_max, their
  /// links `link_diameters` mean grain diameters d long.
  template <int dim>
  DamageZone damage_zone(const dem::Model<dim> &m, std::size_t from, double a, double d,
                         double link_diameters, double r_max = HUGE_VAL)
  {
    return measure_damage_zone(crack_positions(m, from, r_max), a, link_diameters * d,
                               link_diameters);
  }

  /// Cracks (all, since the start) at an in-plane distance > r from the
  /// centre (the axis in 3D): near
  /// an outer boundary (coupling ring or servo membrane) when r is that
  /// boundary's radius less two grain diameters.
  template <int dim>
  std::size_t cracks_beyond(const dem::Model<dim> &m, double r)
  {
    std::size_t n = 0;
    for (const auto &c : m.cracks)
      n += c.position.template head<2>().norm() > r;
    return n;
  }

  /// Whether each grain touches another grain through an active contact
  /// (a bond or a contact carrying force): grains that are not are detached
  /// from the rock mass (a grain flying into the opening).
  template <int dim>
  std::vector<char> attached_grains(const dem::Model<dim> &m)
  {
    std::vector<char> on(m.particles.size(), 0);
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (!grp.is_wall[k] && grp.active(k))
            on[grp.end1[k]] = on[grp.end2[k]] = 1;
      }
    return on;
  }

  /// Mean inward radial displacement (in the xy plane) of the grains whose
  /// reference centre lies within d of the wall r = a and that are still
  /// attached to the rock mass (attached_grains; their count in n; rows x,
  /// y, z, ux, uy, uz with z = 0 in 2D). A detached grain flies on at
  /// constant speed (nothing damps it): counted, one grain of the default
  /// example raised the mean from 3.2 mm to 8.9 mm while the wall stood.
  template <int dim>
  double wall_convergence(const dem::Model<dim> &m, const std::vector<dem::Vec<dim>> &ref,
                          double a, double d, std::size_t *n = nullptr,
                          std::vector<std::array<double, 6>> *rows = nullptr)
  {
    const auto             &P        = m.particles;
    const std::vector<char> attached = attached_grains(m);
    double                  s        = 0;
    std::size_t             c        = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        if (std::size_t(P.id[i]) >= ref.size() || !attached[i])
          continue;
        const dem::Vec<dim> &X = ref[P.id[i]];
        const double         r = X.template head<2>().norm();
        if (r < a + d)
          {
            const dem::Vec<dim> u = P.x[i] - X;
            s -= u.template head<2>().dot(X.template head<2>() / r);
            ++c;
            if (rows)
              rows->push_back({{X[0], X[1], dim == 3 ? X[dim - 1] : 0.0, u[0], u[1],
                                dim == 3 ? u[dim - 1] : 0.0}});
          }
      }
    if (n)
      *n = c;
    return c ? s / c : 0.0;
  }
} // namespace demfem::coupling::excavation
