#include "dem/engine/particles.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace demfem::dem
{
  template <int dim>
  std::size_t Particles<dim>::add(const Vec<dim> &position, double r, double density,
                                  int grp)
  {
    check_range("particle " + std::to_string(size()), "radius", r, 0, HUGE_VAL, true);
    check_range("particle " + std::to_string(size()), "density", density, 0, HUGE_VAL,
                true);
    const double volume = ball_volume<dim>(r);
    const double mss    = density * volume;
    x.push_back(position);
    x0.push_back(position);
    v.push_back(Vec<dim>::Zero());
    w.push_back(RotVec<dim>::Zero());
    f.push_back(Vec<dim>::Zero());
    m.push_back(RotVec<dim>::Zero());
    f_ext.push_back(Vec<dim>::Zero());
    m_ext.push_back(RotVec<dim>::Zero());
    radius.push_back(r);
    mass.push_back(mss);
    inertia.push_back(dim == 2 ? 0.5 * mss * r * r : 0.4 * mss * r * r);
    fixity.push_back(fix_none);
    group.push_back(grp);
    id.push_back(next_id++);
    return size() - 1;
  }

  template <int dim>
  std::vector<std::int64_t> Particles<dim>::remove_if(const std::vector<char> &remove)
  {
    std::vector<std::int64_t> map(size(), -1);
    std::size_t               k = 0;
    for (std::size_t i = 0; i < size(); ++i)
      if (!remove[i])
        {
          map[i] = static_cast<std::int64_t>(k);
          if (k != i)
            {
              x[k]       = x[i];
              x0[k]      = x0[i];
              v[k]       = v[i];
              w[k]       = w[i];
              f[k]       = f[i];
              m[k]       = m[i];
              f_ext[k]   = f_ext[i];
              m_ext[k]   = m_ext[i];
              radius[k]  = radius[i];
              mass[k]    = mass[i];
              inertia[k] = inertia[i];
              fixity[k]  = fixity[i];
              group[k]   = group[i];
              id[k]      = id[i];
            }
          ++k;
        }
    x.resize(k), x0.resize(k), v.resize(k), w.resize(k), f.resize(k), m.resize(k);
    f_ext.resize(k), m_ext.resize(k), radius.resize(k), mass.resize(k);
    inertia.resize(k), fixity.resize(k), group.resize(k), id.resize(k);
    return map;
  }

  template <int dim>
  void Particles<dim>::permute(const std::vector<std::uint32_t> &order)
  {
    auto apply = [&](auto &a) {
      auto b = a;
      for (std::size_t k = 0; k < order.size(); ++k)
        b[k] = a[order[k]];
      a.swap(b);
    };
    apply(x), apply(x0), apply(v), apply(w), apply(f), apply(m), apply(f_ext),
        apply(m_ext);
    apply(radius), apply(mass), apply(inertia), apply(fixity), apply(group), apply(id);
  }

  template <int dim>
  double Particles<dim>::max_radius() const
  {
    return radius.empty() ? 0.0 : *std::max_element(radius.begin(), radius.end());
  }

  template <int dim>
  double Particles<dim>::min_radius() const
  {
    return radius.empty() ? 0.0 : *std::min_element(radius.begin(), radius.end());
  }

  template struct Particles<2>;
  template struct Particles<3>;
} // namespace demfem::dem
