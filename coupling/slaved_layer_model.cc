#include "coupling/slaved_layer_model.h"

#include <deal.II/base/quadrature.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_tools.h>

#include "dem/laws/linear_law.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace demfem::coupling
{
  using dem::Vec;

  template <int dim>
  std::vector<dealii::Point<dim>> SlavedLayerModel<dim>::build_interface(
      std::ostream *progress)
  {
    auto        &P = dem.particles;
    const double b = rp.radius, h = overlap();
    // Temporary ring at r = b for packing and bonding (build_region):
    // facets about two mean grain diameters long (3D: one layer through the
    // slab).
    const unsigned int n =
        std::max(32u, 8 * static_cast<unsigned int>(
                              std::ceil(2 * M_PI * b / (2 * rp.mean_diameter()) / 8)));
    int ring = -1;
    if constexpr (dim == 2)
      {
        ring = dem.walls.add_wall("packing ring");
        std::vector<int> vtx(n);
        for (unsigned int k = 0; k < n; ++k)
          vtx[k] = dem.walls.add_vertex(
              Vec<2>(b * std::cos(2 * M_PI * k / n), b * std::sin(2 * M_PI * k / n)));
        for (unsigned int k = 0; k < n; ++k)
          dem.walls.add_facet(ring, {{vtx[k], vtx[(k + 1) % n]}});
      }
    else
      ring = add_cylinder_ring(dem.walls, b, rp.slab_thickness, n, 1, "packing ring");
    groups = build_region<dim>(dem, rp, progress);

    // Null law (zero stiffness) for the ring's contacts and for contacts
    // between two slaved grains; the ring gets no new contacts.
    typename dem::LinearLaw<dim>::Params null_law; // kn = ks = friction = 0
    null_ball = dem.template add_law<dem::LinearLaw<dim>>(null_law,
                                                          "slaved layer (slaved-slaved)");
    null_wall = dem.template add_law<dem::LinearLaw<dim>>(null_law,
                                                          "slaved layer (packing ring)");
    dem.set_default_law(groups.linear, -1);

    // Slaved grains: centres in the overlap (r > b - h; a 3D section's
    // end layers too: in_continuum).
    std::vector<char> is_slave(P.size(), 0);
    for (std::size_t i = 0; i < P.size(); ++i)
      if (this->in_continuum(P.x[i]))
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
          if (grp.is_wall[k] &&
              (dem.walls.facet_wall[grp.end2[k]] == ring || is_slave[grp.end1[k]]))
            wall.emplace_back(grp.end1[k], grp.end2[k]);
          else if (grp.is_wall[k])
            continue; // a free grain on a slab wall (3D)
          else if (is_slave[grp.end1[k]] && is_slave[grp.end2[k]])
            ball.emplace_back(grp.end1[k], grp.end2[k]);
      }
    for (const auto &[i, k] : wall)
      dem.install_wall(i, k, null_wall);
    for (const auto &[i, j] : ball)
      dem.install(i, j, null_ball);
    const int nb        = null_ball;
    dem.new_contact_law = [nb](const dem::Particles<dim> &Q, std::uint32_t i,
                               std::uint32_t j) {
      return (Q.group[i] == slaved_tag && Q.group[j] == slaved_tag) ? nb : -1;
    };
    if constexpr (dim == 3)
      {
        // New slab-wall contacts: null for slaved grains, else the region's
        // frictionless slab law (build_region's rule). The particles live in
        // this model, whose address does not change.
        const auto                 rule = dem.new_wall_contact_law;
        const int                  nw   = null_wall;
        const dem::Particles<dim> *Q    = &dem.particles;
        dem.new_wall_contact_law = [rule, nw, Q](std::uint32_t i, std::uint32_t k) {
          const int g = rule ? rule(i, k) : -1;
          return g >= 0 && Q->group[i] == slaved_tag ? nw : g;
        };
      }

    // Cell and unit point of every slaved grain; the coupling nodes are the
    // vertices of these cells (sorted by vertex index).
    const auto                          &tria = this->triangulation();
    const dealii::MappingQ<dim>          mapping(1);
    const dealii::FE_Q<dim>              fe(1);
    std::map<unsigned int, unsigned int> node_of; // mesh vertex -> coupling index
    struct Located
    {
      typename dealii::Triangulation<dim>::active_cell_iterator cell;
      dealii::Point<dim>                                        unit;
    };
    std::vector<Located> where;
    slaved.clear();
    for (std::size_t i = 0; i < P.size(); ++i)
      if (is_slave[i])
        {
          dealii::Point<dim> X;
          for (int c = 0; c < dim; ++c)
            X[c] = P.x[i][c];
          const auto found =
              dealii::GridTools::find_active_cell_around_point(mapping, tria, X);
          Slave s;
          s.id = P.id[i];
          s.X  = P.x[i];
          slaved.push_back(s);
          where.push_back({found.first, found.second});
          for (const unsigned int v : found.first->vertex_indices())
            node_of.emplace(found.first->vertex_index(v), 0);
        }
    std::vector<dealii::Point<dim>> pts;
    for (auto &[v, k] : node_of)
      {
        k = static_cast<unsigned int>(pts.size());
        pts.push_back(tria.get_vertices()[v]);
      }
    for (std::size_t s = 0; s < slaved.size(); ++s)
      {
        // Shape values and real-space gradients at X (FE_Q(1): shape a
        // belongs to vertex a).
        const dealii::Quadrature<dim> q(std::vector<dealii::Point<dim>>{where[s].unit},
                                        std::vector<double>{1.0});
        dealii::FEValues<dim>         fv(mapping, fe, q,
                                         dealii::update_values | dealii::update_gradients);
        fv.reinit(typename dealii::Triangulation<dim>::cell_iterator(where[s].cell));
        double sum = 0;
        for (unsigned int a = 0; a < n_nodes; ++a)
          {
            slaved[s].node[a] = node_of.at(where[s].cell->vertex_index(a));
            slaved[s].N[a]    = fv.shape_value(a, 0);
            for (int c = 0; c < dim; ++c)
              slaved[s].dN[a][c] = fv.shape_grad(a, 0)[c];
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

  template <int dim>
  void SlavedLayerModel<dim>::refresh_index() const
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

  template <int dim>
  void SlavedLayerModel<dim>::add_attached_stiffness(std::vector<double> &k) const
  {
    // A slaved grain's contact stiffness (translational kt; rotational kr
    // through the moment map 0.5 m x grad N) is felt by its cell's nodes with
    // the weights of gather_forces. Slaved-slaved contacts are null (zero
    // stiffness), so kt and kr count the free-slaved contacts only.
    refresh_index();
    const auto         &P = dem.particles;
    std::vector<double> kt(P.size(), 0.0), kr(P.size(), 0.0);
    for (int g = 0; g < dem.n_groups(); ++g)
      dem.group(g).accumulate_stiffness(P, kt, kr, dem.touching_gap);
    for (std::size_t s = 0; s < slaved.size(); ++s)
      {
        const auto &S    = slaved[s];
        double      grad = 0;
        for (unsigned int b = 0; b < n_nodes; ++b)
          grad += S.dN[b].norm();
        for (unsigned int a = 0; a < n_nodes; ++a)
          k[S.node[a]] +=
              S.N[a] * kt[index[s]] + 0.25 * S.dN[a].norm() * grad * kr[index[s]];
      }
  }

  template <int dim>
  Vec<dim> SlavedLayerModel<dim>::gather_forces(std::vector<Vec<dim>> &nodal) const
  {
    refresh_index();
    const auto &P = dem.particles;
    for (std::size_t s = 0; s < slaved.size(); ++s)
      {
        const auto     &S = slaved[s];
        const Vec<dim> &f = P.f[index[s]];
        // Work conjugate of v_p and w_p: N_a f + 0.5 m x grad N_a.
        if constexpr (dim == 2)
          {
            const double m = P.m[index[s]][0];
            for (unsigned int a = 0; a < n_nodes; ++a)
              nodal[S.node[a]] += S.N[a] * f + 0.5 * m * Vec<2>(-S.dN[a][1], S.dN[a][0]);
          }
        else
          {
            const Vec<3> m = P.m[index[s]];
            for (unsigned int a = 0; a < n_nodes; ++a)
              nodal[S.node[a]] += S.N[a] * f + 0.5 * m.cross(S.dN[a]);
          }
      }
    // DEM side of the balance: the forces on the slaved ends of the
    // free-slaved contacts (force[k] acts on end2, -force[k] on end1).
    Vec<dim> sum = Vec<dim>::Zero();
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

  template <int dim>
  void SlavedLayerModel<dim>::move_interface(const std::vector<Vec<dim>> &u,
                                             const std::vector<Vec<dim>> &v)
  {
    refresh_index();
    auto &P = dem.particles;
    for (std::size_t s = 0; s < slaved.size(); ++s)
      {
        const auto      &S  = slaved[s];
        Vec<dim>         up = Vec<dim>::Zero(), vp = Vec<dim>::Zero();
        dem::RotVec<dim> w = dem::RotVec<dim>::Zero();
        for (unsigned int a = 0; a < n_nodes; ++a)
          {
            up += S.N[a] * u[S.node[a]];
            vp += S.N[a] * v[S.node[a]];
            if constexpr (dim == 2) // 0.5 curl v
              w[0] += 0.5 * (S.dN[a][0] * v[S.node[a]][1] - S.dN[a][1] * v[S.node[a]][0]);
            else
              w += 0.5 * S.dN[a].cross(v[S.node[a]]);
          }
        const auto i = index[s];
        P.x[i]       = S.X + up; // re-synchronized (round-off only)
        P.v[i]       = vp;
        P.w[i]       = w;
      }
  }

  template class SlavedLayerModel<2>;
  template class SlavedLayerModel<3>;
} // namespace demfem::coupling
