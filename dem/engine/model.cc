#include "dem/engine/model.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace demfem::dem
{
  template <int dim>
  int Model<dim>::add_group(std::unique_ptr<ContactGroupBase<dim>> g)
  {
    groups_.push_back(std::move(g));
    groups_.back()->suspend_breakage(breakage_suspended_);
    return static_cast<int>(groups_.size()) - 1;
  }

  template <int dim>
  void Model<dim>::set_default_law(int ball_ball_group, int ball_wall_group)
  {
    if (ball_ball_group >= n_groups() || ball_wall_group >= n_groups())
      throw InputError("Model::set_default_law: unknown law group");
    default_ball_ = ball_ball_group;
    default_wall_ = ball_wall_group;
  }

  template <int dim>
  std::size_t Model<dim>::n_contacts() const
  {
    std::size_t n = 0;
    for (const auto &g : groups_)
      n += g->size();
    return n;
  }

  template <int dim>
  ContactRef Model<dim>::find(std::uint32_t i, std::uint32_t j, bool wall) const
  {
    if (!wall && i > j)
      std::swap(i, j);
    auto it = index_.find(key(i, j, wall));
    return it == index_.end() ? ContactRef{} : it->second;
  }

  template <int dim>
  void Model<dim>::erase(const ContactRef &c)
  {
    auto &g = *groups_[c.group];
    index_.erase(key(g.end1[c.index], g.end2[c.index], g.is_wall[c.index]));
    const std::size_t last = g.size() - 1;
    if (c.index != last)
      index_[key(g.end1[last], g.end2[last], g.is_wall[last])] = c;
    g.remove(c.index);
  }

  template <int dim>
  ContactRef Model<dim>::install(std::uint32_t i, std::uint32_t j, int group)
  {
    if (i == j || i >= particles.size() || j >= particles.size())
      throw InputError("Model::install: invalid particle pair");
    if (group < 0 || group >= n_groups())
      throw InputError("Model::install: unknown law group " + std::to_string(group));
    if (i > j)
      std::swap(i, j);
    if (auto old = find(i, j); old.group >= 0)
      erase(old);
    ContactRef c{group, groups_[group]->add(i, j, false, particles, walls)};
    index_[key(i, j, false)] = c;
    baseline_valid_          = false;
    return c;
  }

  template <int dim>
  ContactRef Model<dim>::install_wall(std::uint32_t i, std::uint32_t k, int group)
  {
    if (i >= particles.size() || k >= walls.n_facets())
      throw InputError("Model::install_wall: invalid particle or facet");
    if (group < 0 || group >= n_groups())
      throw InputError("Model::install_wall: unknown law group " + std::to_string(group));
    if (auto old = find(i, k, true); old.group >= 0)
      erase(old);
    ContactRef c{group, groups_[group]->add(i, k, true, particles, walls)};
    index_[key(i, k, true)] = c;
    baseline_valid_         = false;
    return c;
  }

  template <int dim>
  ContactRef Model<dim>::reassign(const ContactRef &c, int group)
  {
    auto               &g = *groups_[c.group];
    const std::uint32_t i = g.end1[c.index], j = g.end2[c.index];
    return g.is_wall[c.index] ? install_wall(i, j, group) : install(i, j, group);
  }

  template <int dim>
  void Model<dim>::set_timestep(double dt)
  {
    check_range("Model", "timestep", dt, 0, HUGE_VAL);
    auto_dt_ = (dt == 0);
    dt_      = dt;
  }

  template <int dim>
  double Model<dim>::critical_timestep() const
  {
    const std::size_t   N = particles.size();
    std::vector<double> kt(N, 0.0), kr(N, 0.0);
    for (const auto &g : groups_)
      g->accumulate_stiffness(particles, kt, kr, touching_gap);
    double dt = std::numeric_limits<double>::infinity();
    for (std::size_t p = 0; p < N; ++p)
      {
        if (!(particles.fixity[p] & fix_translation) && kt[p] > 0)
          dt = std::min(dt, std::sqrt(particles.mass[p] / kt[p]));
        if (!(particles.fixity[p] & fix_rotation) && kr[p] > 0)
          dt = std::min(dt, std::sqrt(particles.inertia[p] / kr[p]));
      }
    return dt;
  }

  template <int dim>
  bool Model<dim>::rebuild_needed() const
  {
    if (need_rebuild_ || x_at_rebuild_.size() != particles.size() ||
        wall_at_rebuild_.size() != walls.vertex.size())
      return true;
    const double limit2 = 0.25 * skin * skin; // half the skin
    for (std::size_t i = 0; i < particles.size(); ++i)
      if ((particles.x[i] - x_at_rebuild_[i]).squaredNorm() > limit2)
        return true;
    for (std::size_t i = 0; i < walls.vertex.size(); ++i)
      if ((walls.vertex[i] - wall_at_rebuild_[i]).squaredNorm() > limit2)
        return true;
    return false;
  }

  template <int dim>
  void Model<dim>::detect_contacts()
  {
    if (skin <= 0)
      skin = 0.1 * particles.min_radius();
    std::vector<std::vector<char>> seen(groups_.size());
    for (std::size_t g = 0; g < groups_.size(); ++g)
      seen[g].assign(groups_[g]->size(), 0);
    auto visit = [&](std::uint32_t i, std::uint32_t j, bool wall) {
      auto it = index_.find(key(i, j, wall));
      if (it != index_.end())
        seen[it->second.group][it->second.index] = 1;
      else if (!wall)
        {
          const int g     = new_contact_law ? new_contact_law(particles, i, j) : -1;
          const int group = g >= 0 ? g : default_ball_;
          if (group < 0)
            return;
          if (group >= n_groups())
            throw InputError("Model: new-contact rule returned unknown law group " +
                             std::to_string(group));
          ContactRef c{group, groups_[group]->add(i, j, false, particles, walls)};
          index_[key(i, j, false)] = c;
          seen[c.group].push_back(1);
        }
      else if (wall)
        {
          const int g     = new_wall_contact_law ? new_wall_contact_law(i, j) : -1;
          const int group = g >= 0 ? g : default_wall_;
          if (group < 0)
            return;
          if (group >= n_groups())
            throw InputError("Model: new-wall-contact rule returned unknown law group " +
                             std::to_string(group));
          ContactRef c{group, groups_[group]->add(i, j, true, particles, walls)};
          index_[key(i, j, true)] = c;
          seen[c.group].push_back(1);
        }
    };
    for (const auto &[i, j] : grid_.ball_pairs(particles, skin))
      visit(i, j, false);
    for (const auto &[i, k] : grid_.wall_pairs(particles, walls, skin))
      visit(i, k, true);
    // Contacts whose pieces left the skin are dropped when their law allows
    // (memo §1.6); backwards so swap-removal only moves visited contacts.
    for (std::size_t g = 0; g < groups_.size(); ++g)
      for (std::size_t k = groups_[g]->size(); k-- > 0;)
        if (!seen[g][k] && groups_[g]->deletable(k))
          erase(ContactRef{static_cast<int>(g), k});
    x_at_rebuild_     = particles.x;
    wall_at_rebuild_  = walls.vertex;
    need_rebuild_     = false;
    const double crit = critical_timestep();
    if (auto_dt_)
      dt_ = std::isfinite(crit) ? safety_factor * crit : dt_;
    else if (check_timestep && dt_ > crit)
      {
        std::ostringstream msg;
        msg << "time step " << dt_ << " s is above the critical time step " << crit
            << " s (memo §1.12: min sqrt(m/k)) at step " << step_
            << "; the explicit integration would be unstable. Reduce the time step, "
               "use the automatic time step, or reduce the contact stiffness.";
        throw InstabilityError(msg.str());
      }
  }

  template <int dim>
  void Model<dim>::suppress_duplicate_wall_contacts(ContactGroupBase<dim> &g)
  {
    // A ball touching a wall at an edge or vertex shared by several facets
    // has one contact per facet, all with the same closest point. The wall
    // surface is one surface: only the first of them (lowest facet index)
    // transmits force, or the wall would be twice as stiff along its edges.
    wall_scratch_.clear();
    for (std::size_t k = 0; k < g.size(); ++k)
      if (g.is_wall[k])
        wall_scratch_.push_back(k);
    if (wall_scratch_.size() < 2)
      return;
    std::sort(
        wall_scratch_.begin(), wall_scratch_.end(), [&](std::size_t a, std::size_t b) {
          const int wa = walls.facet_wall[g.end2[a]], wb = walls.facet_wall[g.end2[b]];
          return g.end1[a] != g.end1[b] ? g.end1[a] < g.end1[b]
                 : wa != wb             ? wa < wb
                                        : g.end2[a] < g.end2[b];
        });
    for (std::size_t a = 0; a < wall_scratch_.size(); ++a)
      {
        const std::size_t ka = wall_scratch_[a];
        if (g.force[ka].squaredNorm() == 0 && g.moment[ka].squaredNorm() == 0)
          continue;
        const double tol = 1e-9 * particles.radius[g.end1[ka]];
        for (std::size_t b = a + 1; b < wall_scratch_.size(); ++b)
          {
            const std::size_t kb = wall_scratch_[b];
            if (g.end1[kb] != g.end1[ka] ||
                walls.facet_wall[g.end2[kb]] != walls.facet_wall[g.end2[ka]])
              break;
            if ((g.xc[kb] - g.xc[ka]).squaredNorm() <= tol * tol)
              {
                g.force[kb].setZero();
                g.moment[kb].setZero();
                g.local_force[kb] = ContactForce{};
              }
          }
      }
  }

  template <int dim>
  void Model<dim>::update_incidence()
  {
    // Valid while no group changed its contacts and the particles are the
    // same: contact detection runs every few steps, the scatter every step.
    const std::size_t N = particles.size();
    bool              same =
        incidence_key_.size() == groups_.size() && incidence_start_.size() == N + 1;
    for (std::size_t gi = 0; same && gi < groups_.size(); ++gi)
      same = incidence_key_[gi].first == groups_[gi].get() &&
             incidence_key_[gi].second == groups_[gi]->topology_version();
    if (same)
      return;
    incidence_key_.clear();
    for (const auto &g : groups_)
      incidence_key_.emplace_back(g.get(), g->topology_version());
    // Counting sort by particle, stable: each particle's entries stay in
    // (group, contact) order, the order of the serial scatter, so the sums
    // are bit for bit those of a serial loop over the contacts.
    incidence_start_.assign(N + 1, 0);
    wall_incidence_.clear();
    for (std::size_t gi = 0; gi < groups_.size(); ++gi)
      {
        const auto &g = *groups_[gi];
        for (std::size_t k = 0; k < g.size(); ++k)
          {
            ++incidence_start_[g.end1[k] + 1];
            if (!g.is_wall[k])
              ++incidence_start_[g.end2[k] + 1];
            else
              wall_incidence_.push_back(
                  {static_cast<std::uint32_t>(gi), static_cast<std::uint32_t>(k)});
          }
      }
    for (std::size_t i = 0; i < N; ++i)
      incidence_start_[i + 1] += incidence_start_[i];
    incidence_.resize(incidence_start_[N]);
    std::vector<std::uint32_t> fill(incidence_start_.begin(), incidence_start_.end() - 1);
    for (std::size_t gi = 0; gi < groups_.size(); ++gi)
      {
        const auto &g = *groups_[gi];
        for (std::size_t k = 0; k < g.size(); ++k)
          {
            // side bit 0: piece 1 (receives -F), 1: piece 2 (receives +F)
            const auto c                  = static_cast<std::uint32_t>(k) << 1;
            incidence_[fill[g.end1[k]]++] = {static_cast<std::uint32_t>(gi), c};
            if (!g.is_wall[k])
              incidence_[fill[g.end2[k]]++] = {static_cast<std::uint32_t>(gi), c | 1u};
          }
      }
  }

  template <int dim>
  void Model<dim>::scatter_forces()
  {
    // Each particle sums its contacts' forces and moments in (group,
    // contact) order: the same additions as a serial loop over the contacts,
    // so the result does not depend on the thread count; the particles are
    // independent, so the loop runs on threads.
    update_incidence();
    const std::size_t N = particles.size();
#pragma omp parallel for schedule(static) if (N > parallel_threshold)
    for (std::size_t i = 0; i < N; ++i)
      {
        Vec<dim>    f = Vec<dim>::Zero();
        RotVec<dim> m = RotVec<dim>::Zero();
        for (std::uint32_t e = incidence_start_[i]; e < incidence_start_[i + 1]; ++e)
          {
            const auto        &g = *groups_[incidence_[e].group];
            const std::size_t  k = incidence_[e].contact >> 1;
            const Vec<dim>    &F = g.force[k];
            const RotVec<dim> &M = g.moment[k];
            const Vec<dim>     r = g.xc[k] - particles.x[i];
            if (incidence_[e].contact & 1u)
              {
                f += F;
                if constexpr (dim == 3)
                  m += M + r.cross(F);
                else
                  m[0] += M[0] + cross2(r, F);
              }
            else
              {
                f -= F;
                if constexpr (dim == 3)
                  m -= M + r.cross(F);
                else
                  m[0] -= M[0] + cross2(r, F);
              }
          }
        particles.f[i] = f;
        particles.m[i] = m;
      }
    for (const auto &w : wall_incidence_)
      {
        const auto &g = *groups_[w.group];
        const auto  k = w.contact;
        for (int a = 0; a < dim; ++a)
          walls.vertex_force[walls.facet[g.end2[k]][a]] +=
              g.facet_weights[k][a] * g.force[k];
      }
  }

  template <int dim>
  void Model<dim>::compute_forces()
  {
    for (auto &v : walls.vertex_force)
      v.setZero();
    sinks_.resize(std::max(1, omp_get_max_threads()));
    for (std::size_t gi = 0; gi < groups_.size(); ++gi)
      {
        auto &g = *groups_[gi];
        for (auto &s : sinks_)
          s.events.clear();
        g.compute(particles, walls, dt_, sinks_);
        suppress_duplicate_wall_contacts(g);
        // Events of this group, in contact order whatever the thread count.
        std::vector<std::pair<std::size_t, LawEvent>> ev;
        for (auto &s : sinks_)
          ev.insert(ev.end(), s.events.begin(), s.events.end());
        if (ev.empty())
          continue;
        std::stable_sort(ev.begin(), ev.end(), [](const auto &a, const auto &b) {
          return a.first != b.first ? a.first < b.first
                                    : a.second.element < b.second.element;
        });
        for (const auto &[k, e] : ev)
          {
            const std::int64_t id1 = particles.id[g.end1[k]];
            const std::int64_t id2 = g.is_wall[k]
                                         ? -1 - static_cast<std::int64_t>(g.end2[k])
                                         : particles.id[g.end2[k]];
            if (e.kind == LawEvent::bond_break)
              {
                CrackRecord<dim> c;
                c.id1 = id1, c.id2 = id2, c.element = e.element, c.mode = e.mode;
                c.type           = g.bond_type();
                const Vec<dim> n = g.n_prev[k];
                Vec<dim>       t;
                if constexpr (dim == 3)
                  t          = n.cross(g.s_axis[k]),
                  c.position = g.xc[k] + e.r_s * g.s_axis[k] + e.r_t * t;
                else
                  t = Vec<2>(-n[1], n[0]), c.position = g.xc[k] + e.r_t * t;
                c.normal = n;
                if (e.has_normal)
                  for (int a = 0; a < dim; ++a)
                    c.normal[a] = e.normal[a];
                c.offset            = c.position - g.xc[k];
                c.size              = e.size;
                c.gap               = e.gap;
                c.gap_break         = e.gap;
                c.contact_gap_break = g.gap[k];
                c.strength          = e.strength;
                c.step              = step_;
                c.time              = time_;
                cracks.push_back(c);
                if (on_crack)
                  on_crack(c);
              }
            else if (on_slip)
              on_slip(
                  SlipRecord{id1, id2, e.element, e.kind == LawEvent::slip_start, step_});
          }
      }
    // Forces of all groups to the pieces (nothing above reads them).
    scatter_forces();
  }

  template <int dim>
  void Model<dim>::integrate()
  {
    const std::size_t N     = particles.size();
    const double      dt    = dt_;
    const double      alpha = local_damping;
    auto             &P     = particles;
    int               bad   = -1;
    double            power = 0; // power delivered to the assembly from outside
#pragma omp parallel for schedule(static) reduction(+ : power) if (N > parallel_threshold)
    for (std::size_t i = 0; i < N; ++i)
      {
        if (P.fixity[i] & fix_translation) // the agent holding it does -f.v
          power -= P.f[i].dot(P.v[i]);
        else
          power += (P.f_ext[i] + P.mass[i] * gravity).dot(P.v[i]);
        if (P.fixity[i] & fix_rotation)
          power -= P.m[i].dot(P.w[i]);
        else
          power += P.m_ext[i].dot(P.w[i]);
        if (!(P.fixity[i] & fix_translation))
          {
            Vec<dim> F = P.f[i] + P.f_ext[i] + P.mass[i] * gravity;
            for (int d = 0; d < dim; ++d) // local damping (PFC): -alpha |F| sign(v)
              F[d] -= alpha * std::abs(F[d]) * ((P.v[i][d] > 0) - (P.v[i][d] < 0));
            P.v[i] += (dt / P.mass[i]) * F;
          }
        if (!(P.fixity[i] & fix_rotation))
          {
            RotVec<dim> M = P.m[i] + P.m_ext[i];
            for (int d = 0; d < rot_dim<dim>; ++d)
              M[d] -= alpha * std::abs(M[d]) * ((P.w[i][d] > 0) - (P.w[i][d] < 0));
            P.w[i] += (dt / P.inertia[i]) * M;
          }
        P.x[i] += dt * P.v[i];
        if (!P.x[i].allFinite() || !P.w[i].allFinite())
          {
#pragma omp critical
            bad = static_cast<int>(i);
          }
      }
    for (std::size_t v = 0; v < walls.vertex.size(); ++v)
      power -= walls.vertex_force[v].dot(walls.vertex_velocity[v]);
    work_in_ += power * dt;
    walls.move(dt);
    if (bad >= 0)
      {
        std::ostringstream msg;
        msg << "particle " << P.id[bad]
            << " has a non-finite position or velocity at step " << step_
            << " (time step " << dt_ << " s, critical " << critical_timestep()
            << " s): the run diverged; check the time step and contact stiffnesses.";
        throw InstabilityError(msg.str());
      }
  }

  template <int dim>
  void Model<dim>::step()
  {
    if (rebuild_needed())
      detect_contacts();
    if (auto_dt_ && !(dt_ > 0))
      if (const double crit = critical_timestep(); std::isfinite(crit))
        dt_ = safety_factor * crit;
    if (!(dt_ > 0))
      throw InputError(
          "Model::step: no time step (no contacts to estimate it from; set one)");
    // The energy-balance check below needs the strain energy of the state
    // this step's force pass produces: evaluate it in that pass.
    if (!baseline_valid_ || (step_ + 1) % 10 == 0)
      for (auto &g : groups_)
        g->request_strain_energy();
    compute_forces();
    integrate();
    ++step_;
    time_ += dt_;
    // Exponential growth of kinetic energy is the signature of an unstable
    // explicit integration. Physical transients do not grow by 1.5x per step
    // for 15 consecutive steps (1.5^15 ~ 440): a start from rest under a
    // constant load grows as t^2 (ratio < 1.5 after 4 steps), a wave front
    // spreading through a 3D assembly as ~n^3 (ratio < 1.5 after ~7 steps).
    if (!baseline_valid_ || step_ % 10 == 0)
      {
        check_energy_balance();
        // Contacts stiffen and appear between detection passes: keep the
        // automatic step at safety x critical.
        if (auto_dt_)
          if (const double crit = critical_timestep(); std::isfinite(crit))
            dt_ = safety_factor * crit;
      }
    // Free degrees of freedom only: a prescribed motion (fixity, e.g. grains
    // slaved to a continuum) is not this integration's. Growth counts only
    // above the round-off level of the motion, the kinetic energy of the
    // free mass at one unit of round-off of the positions per step, 0.5 m
    // (eps |x|max / dt)^2: below it a start from rest can be driven by a
    // super-exponential numerical wave tail (a slaved layer in a continuum
    // whose far-field ramp has not arrived yet; measured 1e-51 J growing
    // 1.5x per step), and a genuine instability crosses it within a few
    // steps.
    double ke = 0, free_mass = 0, xmax = 0;
    for (std::size_t i = 0; i < particles.size(); ++i)
      {
        if (!(particles.fixity[i] & fix_translation))
          {
            ke += 0.5 * particles.mass[i] * particles.v[i].squaredNorm();
            free_mass += particles.mass[i];
          }
        if (!(particles.fixity[i] & fix_rotation))
          ke += 0.5 * particles.inertia[i] * particles.w[i].squaredNorm();
        xmax = std::max(xmax, particles.x[i].cwiseAbs().maxCoeff());
      }
    const double v_roundoff = std::numeric_limits<double>::epsilon() * xmax / dt_;
    const double ke_floor   = 0.5 * free_mass * v_roundoff * v_roundoff;
    // Growth of a constant ratio per step above that floor: the rule and its
    // thresholds are common/growth_monitor.h (dem_kinetic_energy).
    const bool unstable = ke_growth_.update(ke, ke_floor);
    if (unstable)
      {
        std::ostringstream msg;
        if (std::isfinite(ke))
          msg << "kinetic energy grew by more than "
              << instability::dem_kinetic_energy.factor << "x per step for "
              << instability::dem_kinetic_energy.steps << " steps (now " << ke
              << " J at step " << step_ << "): numerical instability.";
        else
          msg << "non-finite kinetic energy at step " << step_
              << ": numerical instability.";
        msg << " Time step " << dt_ << " s, critical estimate " << critical_timestep()
            << " s; likely causes: time step above critical, too little damping, or a "
               "stiffness contrast between coupled parts.";
        throw InstabilityError(msg.str());
      }
  }

  template <int dim>
  void Model<dim>::cycle(std::int64_t n)
  {
    for (std::int64_t s = 0; s < n; ++s)
      step();
  }

  template <int dim>
  void Model<dim>::remove_particles(const std::vector<char> &remove)
  {
    for (std::size_t g = 0; g < groups_.size(); ++g)
      for (std::size_t k = groups_[g]->size(); k-- > 0;)
        {
          auto &G = *groups_[g];
          if (remove[G.end1[k]] || (!G.is_wall[k] && remove[G.end2[k]]))
            erase(ContactRef{static_cast<int>(g), k});
        }
    remap_contacts(particles.remove_if(remove));
    need_rebuild_   = true;
    baseline_valid_ = false;
  }

  template <int dim>
  void Model<dim>::remap_contacts(const std::vector<std::int64_t> &map)
  {
    index_.clear();
    for (std::size_t g = 0; g < groups_.size(); ++g)
      {
        auto &G = *groups_[g];
        G.topology_changed();
        for (std::size_t k = 0; k < G.size(); ++k)
          {
            G.end1[k] = static_cast<std::uint32_t>(map[G.end1[k]]);
            if (!G.is_wall[k])
              G.end2[k] = static_cast<std::uint32_t>(map[G.end2[k]]);
            index_[key(G.end1[k], G.end2[k], G.is_wall[k])] =
                ContactRef{static_cast<int>(g), k};
          }
      }
  }

  template <int dim>
  void Model<dim>::reorder_by_cell()
  {
    const std::size_t N = particles.size();
    if (N < 2)
      return;
    // Cells of one largest diameter, visited in Morton (Z) order.
    Vec<dim> lo = particles.x[0];
    for (const auto &x : particles.x)
      lo = lo.cwiseMin(x);
    const double h      = 2 * particles.max_radius();
    auto         morton = [&](const Vec<dim> &x) {
      std::uint64_t code = 0;
      std::uint32_t c[3] = {0, 0, 0};
      for (int d = 0; d < dim; ++d)
        c[d] = static_cast<std::uint32_t>(std::min((x[d] - lo[d]) / h, 1048575.0));
      for (int bit = 0; bit < 21; ++bit)
        for (int d = 0; d < dim; ++d)
          code |= static_cast<std::uint64_t>((c[d] >> bit) & 1u) << (dim * bit + d);
      return code;
    };
    std::vector<std::uint64_t> code(N);
    for (std::size_t i = 0; i < N; ++i)
      code[i] = morton(particles.x[i]);
    std::vector<std::uint32_t> order(N);
    for (std::size_t i = 0; i < N; ++i)
      order[i] = static_cast<std::uint32_t>(i);
    std::stable_sort(order.begin(), order.end(),
                     [&](auto a, auto b) { return code[a] < code[b]; });
    std::vector<std::int64_t> map(N);
    for (std::size_t k = 0; k < N; ++k)
      map[order[k]] = static_cast<std::int64_t>(k);
    particles.permute(order);
    remap_contacts(map);
    need_rebuild_ = true;
  }

  template class Model<2>;
  template class Model<3>;
} // namespace demfem::dem
