#include "dem/specimen/joint_insertion.h"

#include <utility>
#include <vector>

namespace demfem::dem
{
  template <int dim>
  std::size_t insert_smooth_joint(Model<dim> &model, const JointPlane<dim> &plane,
                                  int &group, const std::string &where)
  {
    group = model.template add_law<SmoothJointLaw<dim>>(plane.sj, where);
    // Collect first: install() moves contacts between groups.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> across;
    for (int g = 0; g < model.n_groups(); ++g)
      {
        if (g == group)
          continue;
        const auto &G = model.group(g);
        for (std::size_t k = 0; k < G.size(); ++k)
          if (!G.is_wall[k] &&
              plane.crosses(model.particles.x[G.end1[k]], model.particles.x[G.end2[k]]))
            across.emplace_back(G.end1[k], G.end2[k]);
      }
    for (const auto &[i, j] : across)
      model.install(i, j, group);
    const int previous_rule_group = group;
    auto      previous            = model.new_contact_law;
    // The rule reads positions from the particles it is given, so it stays
    // valid when the model is moved.
    model.new_contact_law = [plane, previous_rule_group,
                             previous](const Particles<dim> &p, std::uint32_t i,
                                       std::uint32_t j) {
      if (plane.crosses(p.x[i], p.x[j]))
        return previous_rule_group;
      return previous ? previous(p, i, j) : -1;
    };
    return across.size();
  }

  template std::size_t insert_smooth_joint<2>(Model<2> &, const JointPlane<2> &, int &,
                                              const std::string &);
  template std::size_t insert_smooth_joint<3>(Model<3> &, const JointPlane<3> &, int &,
                                              const std::string &);
} // namespace demfem::dem
