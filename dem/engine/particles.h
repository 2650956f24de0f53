#pragma once
// Particles (2D unit-thickness disks, 3D spheres) in structure-of-arrays form.
#include "dem/engine/types.h"

#include <cstdint>
#include <vector>

namespace demfem::dem
{
  /// Fixity bits: a fixed degree of freedom keeps the velocity the user set.
  enum Fixity : std::uint8_t
  {
    fix_none        = 0,
    fix_translation = 1,
    fix_rotation    = 2,
    fix_all         = 3
  };

  template <int dim>
  struct Particles
  {
    std::vector<Vec<dim>>    x;        ///< centre
    std::vector<Vec<dim>>    v;        ///< translational velocity (half step)
    std::vector<RotVec<dim>> w;        ///< angular velocity (2D: about z)
    std::vector<Vec<dim>>    f;        ///< resultant force of the step
    std::vector<RotVec<dim>> m;        ///< resultant moment of the step
    std::vector<Vec<dim>>    f_ext;    ///< applied external force (persistent)
    std::vector<RotVec<dim>> m_ext;    ///< applied external moment (persistent)
    std::vector<Vec<dim>>    x0;       ///< reference position for displacement
    std::vector<double>      radius;
    std::vector<double>      mass;
    std::vector<double>      inertia;  ///< 2D: m r^2 / 2 (disk); 3D: 2 m r^2 / 5
    std::vector<std::uint8_t> fixity;
    std::vector<int>         group;    ///< user tag (e.g. grip, slaved, region)
    std::vector<std::int64_t> id;      ///< stable id across deletions

    std::size_t size() const { return x.size(); }

    /// Adds a particle of the given radius and density; returns its index.
    /// Mass uses unit thickness in 2D. Throws InputError for r <= 0 or
    /// density <= 0.
    std::size_t add(const Vec<dim> &position, double r, double density, int grp = 0);

    /// Removes the particles flagged in `remove` (keeps order of the rest);
    /// returns the old->new index map (-1 for removed).
    std::vector<std::int64_t> remove_if(const std::vector<char> &remove);

    /// Reorders the particles: new index k holds old particle order[k].
    void permute(const std::vector<std::uint32_t> &order);

    /// Id the next added particle receives (saved by checkpoints so that
    /// ids stay unique across a restart).
    std::int64_t next_particle_id() const { return next_id; }
    void         set_next_particle_id(std::int64_t n) { next_id = n; }

    double max_radius() const;
    double min_radius() const;

  private:
    std::int64_t next_id = 0;
  };
} // namespace demfem::dem
