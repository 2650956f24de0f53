#include "dem/measure/particle_stress.h"

#include <cmath>

namespace demfem::dem
{
  template <int dim>
  std::vector<StressTensor<dim>> grain_stresses(const Model<dim> &model,
                                                double            solid_fraction)
  {
    check_range("grain_stresses", "solid fraction", solid_fraction, 0, 1, true);
    const auto                    &P = model.particles;
    std::vector<StressTensor<dim>> s(P.size(), StressTensor<dim>::Zero());
    for (int g = 0; g < model.n_groups(); ++g)
      {
        const auto &grp = model.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          {
            // force[k] acts on piece 2; piece 1 (always a grain) gets -force.
            const auto i = grp.end1[k];
            s[i] -= (grp.xc[k] - P.x[i]) * grp.force[k].transpose();
            if (!grp.is_wall[k])
              {
                const auto j = grp.end2[k];
                s[j] += (grp.xc[k] - P.x[j]) * grp.force[k].transpose();
              }
          }
      }
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        const double r = P.radius[i];
        const double V = ball_volume<dim>(r);
        // eval(): a = a + a^T aliases in Eigen.
        const StressTensor<dim> sym = s[i] + s[i].transpose();
        s[i]                        = (0.5 * solid_fraction / V) * sym;
      }
    return s;
  }

  template std::vector<StressTensor<2>> grain_stresses(const Model<2> &, double);
  template std::vector<StressTensor<3>> grain_stresses(const Model<3> &, double);
} // namespace demfem::dem
