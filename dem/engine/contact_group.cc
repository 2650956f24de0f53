#include "dem/engine/contact_group.h"

namespace demfem::dem
{
  const char *bond_type_name(BondType t)
  {
    switch (t)
      {
      case BondType::contact_bond:
        return "contact_bond";
      case BondType::parallel_bond:
        return "parallel_bond";
      case BondType::flat_joint:
        return "flat_joint";
      case BondType::smooth_joint:
        return "smooth_joint";
      default:
        return "none";
      }
  }

  template <>
  Vec<2> initial_s_axis<2>(const Vec<2> &)
  {
    return Vec<2>::Zero();
  }

  template <>
  Vec<3> initial_s_axis<3>(const Vec<3> &n)
  {
    // Project global x (or y when x is nearly parallel to n) onto the plane.
    Vec<3> e = std::abs(n[0]) < 0.9 ? Vec<3>::UnitX() : Vec<3>::UnitY();
    Vec<3> s = e - e.dot(n) * n;
    return s.normalized();
  }

  template <int dim>
  std::size_t ContactGroupBase<dim>::add(std::uint32_t i, std::uint32_t j, bool wall,
                                         const Particles<dim> &p, const Walls<dim> &w)
  {
    const std::size_t k = size();
    energy_fresh_       = false;
    ++topology_;
    end1.push_back(i);
    end2.push_back(j);
    is_wall.push_back(wall);
    s_axis.push_back(Vec<dim>::Zero());
    n_prev.push_back(Vec<dim>::UnitX());
    xc.push_back(Vec<dim>::Zero());
    gap.push_back(0);
    local_force.push_back(ContactForce{});
    force.push_back(Vec<dim>::Zero());
    moment.push_back(RotVec<dim>::Zero());
    facet_weights.push_back({});
    state_.resize(state_.size() + stride(), 0.0);
    ContactGeometry<dim> g = geometry(k, p, w, &facet_weights[k]);
    n_prev[k]              = g.n;
    if constexpr (dim == 3)
      {
        s_axis[k] = initial_s_axis<3>(g.n);
        g.s       = s_axis[k];
        g.t       = g.n.cross(g.s);
      }
    xc[k]  = g.xc;
    gap[k] = g.gap;
    install(k, g);
    return k;
  }

  template <int dim>
  void ContactGroupBase<dim>::remove(std::size_t k)
  {
    const std::size_t last = size() - 1;
    energy_fresh_          = false;
    ++topology_;
    if (k != last)
      {
        end1[k]          = end1[last];
        end2[k]          = end2[last];
        is_wall[k]       = is_wall[last];
        s_axis[k]        = s_axis[last];
        n_prev[k]        = n_prev[last];
        xc[k]            = xc[last];
        gap[k]           = gap[last];
        local_force[k]   = local_force[last];
        force[k]         = force[last];
        moment[k]        = moment[last];
        facet_weights[k] = facet_weights[last];
        const int n      = stride();
        std::copy(&state_[last * n], &state_[last * n] + n, &state_[k * n]);
      }
    end1.pop_back(), end2.pop_back(), is_wall.pop_back(), s_axis.pop_back();
    n_prev.pop_back(), xc.pop_back(), gap.pop_back(), local_force.pop_back();
    force.pop_back(), moment.pop_back(), facet_weights.pop_back();
    state_.resize(state_.size() - stride());
  }

  template class ContactGroupBase<2>;
  template class ContactGroupBase<3>;
} // namespace demfem::dem
