#include "coupling/slaved_layer_model.h"

#include <deal.II/base/quadrature.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_tools.h>

#include "dem/linear_law.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace demfem::coupling
{
  using dem::Vec;

  std::vector<dealii::Point<2>> SlavedLayerModel::build_interface(std::ostream *progress)
  {
    auto        &P = dem.particles;
    const double b = rp.radius, h = overlap();
    // Temporary ring at r = b for packing and bonding (build_disk_region):
    // facets about two mean grain diameters long.
    const unsigned int n =
        std::max(32u, 8 * static_cast<unsigned int>(
                              std::ceil(2 * M_PI * b / (2 * rp.mean_diameter()) / 8)));
    const int        ring = dem.walls.add_wall("packing ring");
    std::vector<int> vtx(n);
    for (unsigned int k = 0; k < n; ++k)
      vtx[k] = dem.walls.add_vertex(
          Vec<2>(b * std::cos(2 * M_PI * k / n), b * std::sin(2 * M_PI * k / n)));
    for (unsigned int k = 0; k < n; ++k)
      dem.walls.add_facet(ring, {vtx[k], vtx[(k + 1) % n]});
    groups = build_disk_region(dem, rp, progress);

    // Null law (zero stiffness) for the ring's contacts and for contacts
    // between two slaved grains; the ring gets no new contacts.
    dem::LinearLaw<2>::Params null_law; // kn = ks = friction = 0
    null_ball = dem.add_law<dem::LinearLaw<2>>(null_law, "slaved layer (slaved-slaved)");
    null_wall = dem.add_law<dem::LinearLaw<2>>(null_law, "slaved layer (packing ring)");
    dem.set_default_law(groups.linear, -1);

    // Slaved grains: centres in the overlap.
    std::vector<char> is_slave(P.size(), 0);
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.x[i].norm() > b - h)
        {
          is_slave[i] = 1;
          P.fixity[i] = dem::fix_all;
          P.group[i]  = slaved_tag;
          P.v[i].setZero();
          P.w[i].setZero();
        }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> ball, wall;
    for (int g = 0; g < dem.n_groups(); ++g)
      {
        const auto &grp = dem.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (grp.is_wall[k])
            wall.emplace_back(grp.end1[k], grp.end2[k]);
          else if (is_slave[grp.end1[k]] && is_slave[grp.end2[k]])
            ball.emplace_back(grp.end1[k], grp.end2[k]);
      }
    for (const auto &[i, k] : wall)
      dem.install_wall(i, k, null_wall);
    for (const auto &[i, j] : ball)
      dem.install(i, j, null_ball);
    const int nb        = null_ball;
    dem.new_contact_law = [nb](const dem::Particles<2> &Q, std::uint32_t i,
                               std::uint32_t j) {
      return (Q.group[i] == slaved_tag && Q.group[j] == slaved_tag) ? nb : -1;
    };

    // Cell and unit point of every slaved grain; the coupling nodes are the
    // vertices of these cells (sorted by vertex index).
    const auto                          &tria = triangulation();
    const dealii::MappingQ<2>            mapping(1);
    const dealii::FE_Q<2>                fe(1);
    std::map<unsigned int, unsigned int> node_of; // mesh vertex -> coupling index
    struct Located
    {
      dealii::Triangulation<2>::active_cell_iterator cell;
      dealii::Point<2>                               unit;
    };
    std::vector<Located> where;
    slaved.clear();
    for (std::size_t i = 0; i < P.size(); ++i)
      if (is_slave[i])
        {
          const dealii::Point<2> X(P.x[i][0], P.x[i][1]);
          const auto             found =
              dealii::GridTools::find_active_cell_around_point(mapping, tria, X);
          Slave s;
          s.id = P.id[i];
          s.X  = P.x[i];
          slaved.push_back(s);
          where.push_back({found.first, found.second});
          for (const unsigned int v : found.first->vertex_indices())
            node_of.emplace(found.first->vertex_index(v), 0);
        }
    std::vector<dealii::Point<2>> pts;
    for (auto &[v, k] : node_of)
      {
        k = static_cast<unsigned int>(pts.size());
        pts.push_back(tria.get_vertices()[v]);
      }
    for (std::size_t s = 0; s < slaved.size(); ++s)
      {
        // Shape values and real-space gradients at X (FE_Q(1): shape a
        // belongs to vertex a).
        const dealii::Quadrature<2> q(std::vector<dealii::Point<2>>{where[s].unit},
                                      std::vector<double>{1.0});
        dealii::FEValues<2>         fv(mapping, fe, q,
                                       dealii::update_values | dealii::update_gradients);
        fv.reinit(typename dealii::Triangulation<2>::cell_iterator(where[s].cell));
        double sum = 0;
        for (unsigned int a = 0; a < 4; ++a)
          {
            slaved[s].node[a] = node_of.at(where[s].cell->vertex_index(a));
            slaved[s].N[a]    = fv.shape_value(a, 0);
            slaved[s].dN[a]   = Vec<2>(fv.shape_grad(a, 0)[0], fv.shape_grad(a, 0)[1]);
            sum += slaved[s].N[a];
          }
        if (std::abs(sum - 1) > 1e-12 ||
            *std::min_element(slaved[s].N.begin(), slaved[s].N.end()) < -1e-9)
          throw std::runtime_error("slaved layer: grain " + std::to_string(slaved[s].id) +
                                   " is not inside its located cell");
      }
    index.clear();
    refresh_index();
    dem.invalidate_contacts();
    if (progress)
      *progress << "slaved layer: overlap h = " << h << " m (continuum from r = " << b - h
                << " m), " << slaved.size() << " slaved grains, " << ball.size()
                << " slaved-slaved contacts nulled, " << pts.size()
                << " coupling nodes\n";
    return pts;
  }

  void SlavedLayerModel::refresh_index() const
  {
    const auto &P  = dem.particles;
    bool        ok = index.size() == slaved.size() && index_n == P.size();
    for (std::size_t s = 0; ok && s < slaved.size(); ++s)
      ok = index[s] >= 0 && std::size_t(index[s]) < P.size() &&
           P.id[index[s]] == slaved[s].id;
    if (ok)
      return;
    std::map<std::int64_t, std::int64_t> by_id;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.group[i] == slaved_tag)
        by_id[P.id[i]] = std::int64_t(i);
    index.assign(slaved.size(), -1);
    for (std::size_t s = 0; s < slaved.size(); ++s)
      {
        const auto it = by_id.find(slaved[s].id);
        if (it == by_id.end())
          throw std::runtime_error("slaved layer: slaved grain " +
                                   std::to_string(slaved[s].id) + " was removed");
        index[s] = it->second;
      }
    index_n = P.size();
  }

  Vec<2> SlavedLayerModel::gather_forces(std::vector<Vec<2>> &nodal) const
  {
    refresh_index();
    const auto &P = dem.particles;
    for (std::size_t s = 0; s < slaved.size(); ++s)
      {
        const auto   &S = slaved[s];
        const Vec<2> &f = P.f[index[s]];
        const double  m = P.m[index[s]][0];
        for (int a = 0; a < 4; ++a) // work conjugate of v_p and w_p
          nodal[S.node[a]] += S.N[a] * f + 0.5 * m * Vec<2>(-S.dN[a][1], S.dN[a][0]);
      }
    // DEM side of the balance: the forces on the slaved ends of the
    // free-slaved contacts (force[k] acts on end2, -force[k] on end1).
    Vec<2> sum = Vec<2>::Zero();
    for (int g = 0; g < dem.n_groups(); ++g)
      {
        const auto &grp = dem.group(g);
        for (std::size_t k = 0; k < grp.size(); ++k)
          if (!grp.is_wall[k])
            {
              const bool s1 = P.group[grp.end1[k]] == slaved_tag,
                         s2 = P.group[grp.end2[k]] == slaved_tag;
              if (s2 && !s1)
                sum += grp.force[k];
              else if (s1 && !s2)
                sum -= grp.force[k];
            }
      }
    return sum;
  }

  void SlavedLayerModel::move_interface(const std::vector<Vec<2>> &u,
                                        const std::vector<Vec<2>> &v)
  {
    refresh_index();
    auto &P = dem.particles;
    for (std::size_t s = 0; s < slaved.size(); ++s)
      {
        const auto &S  = slaved[s];
        Vec<2>      up = Vec<2>::Zero(), vp = Vec<2>::Zero();
        double      w = 0;
        for (int a = 0; a < 4; ++a)
          {
            up += S.N[a] * u[S.node[a]];
            vp += S.N[a] * v[S.node[a]];
            w += 0.5 * (S.dN[a][0] * v[S.node[a]][1] - S.dN[a][1] * v[S.node[a]][0]);
          }
        const auto i = index[s];
        P.x[i]       = S.X + up; // re-synchronized (round-off only)
        P.v[i]       = vp;
        P.w[i][0]    = w;
      }
  }
} // namespace demfem::coupling
