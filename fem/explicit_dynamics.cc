#include "fem/explicit_dynamics.h"
#include "fem/isotropic_elasticity.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace demfem::fem
{
  using namespace dealii;

  template <int dim>
  ExplicitDynamics<dim>::ExplicitDynamics(
      const parallel::distributed::Triangulation<dim> &tria, const ExplicitSettings &s)
      : triangulation(tria)
      , settings(s)
      , comm(tria.get_communicator())
      , fe(FE_Q<dim>(s.degree), dim)
      , mapping(s.degree)
      , dof_handler(tria)
  {
    AssertThrow(s.young_modulus > 0, ExcMessage("young modulus must be > 0"));
    AssertThrow(s.poisson_ratio > -1 && s.poisson_ratio < 0.5,
                ExcMessage("poisson ratio must lie in (-1, 0.5)"));
    AssertThrow(s.density > 0 && s.mass_scaling > 0,
                ExcMessage("density and mass scaling must be > 0"));
    AssertThrow(s.damping >= 0, ExcMessage("damping must be >= 0"));
  }

  template <int dim>
  ExplicitDynamics<dim>::~ExplicitDynamics()
  {
    dof_handler.clear();
  }

  template <int dim>
  void ExplicitDynamics<dim>::setup()
  {
    dof_handler.distribute_dofs(fe);
    owned = dof_handler.locally_owned_dofs();
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);

    DynamicSparsityPattern dsp(relevant);
    DoFTools::make_sparsity_pattern(dof_handler, dsp);
    SparsityTools::distribute_sparsity_pattern(dsp, owned, comm, relevant);
    stiffness.reinit(owned, owned, dsp, comm);
    for (auto *vec : {&mass, &u, &v, &f_ext, &work, &f_boundary})
      vec->reinit(owned, comm);
    boundary_factor = 0;

    const double        E = settings.young_modulus, nu = settings.poisson_ratio;
    const LameConstants elastic = lame_constants(E, nu);
    const double        rho     = settings.density * settings.mass_scaling;

    const QGauss<dim>                    quadrature(fe.degree + 1);
    FEValues<dim>                        fe_values(mapping, fe, quadrature,
                                                   update_values | update_gradients | update_JxW_values);
    const unsigned int                   n = fe.n_dofs_per_cell();
    FullMatrix<double>                   cell_k(n, n);
    Vector<double>                       cell_m(n);
    std::vector<types::global_dof_index> dofs(n);
    std::vector<SymmetricTensor<2, dim>> eps(n);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_k = 0;
          cell_m = 0;
          fe_values.reinit(cell);
          add_isotropic_stiffness(fe_values, elastic, eps, cell_k);
          for (const unsigned int q : fe_values.quadrature_point_indices())
            for (unsigned int i = 0; i < n; ++i)
              // Row-sum lumping: sum_j int rho phi_i.phi_j = int rho phi_i
              // over the component of i (the scalar shapes sum to one).
              cell_m(i) += rho *
                           fe_values.shape_value_component(
                               i, q, fe.system_to_component_index(i).first) *
                           fe_values.JxW(q);
          cell->get_dof_indices(dofs);
          stiffness.add(dofs, cell_k);
          for (unsigned int i = 0; i < n; ++i)
            mass(dofs[i]) += cell_m(i);
        }
    stiffness.compress(VectorOperation::add);
    mass.compress(VectorOperation::add);

    // Zero-displacement dofs (owned ones; each rank updates only its own).
    // Ghost cells are searched too: an owned dof may lie only on boundary
    // faces of cells owned by another rank.
    std::map<types::global_dof_index, unsigned int> fixed;
    std::vector<types::global_dof_index>            face_dofs(fe.n_dofs_per_face());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            for (const auto &[id, comps] : settings.fixed)
              if (face->boundary_id() == id)
                {
                  face->get_dof_indices(face_dofs);
                  for (unsigned int i = 0; i < face_dofs.size(); ++i)
                    {
                      const unsigned int c = fe.face_system_to_component_index(i).first;
                      if (c < comps.size() && comps[c] && owned.is_element(face_dofs[i]))
                        fixed.emplace(face_dofs[i], c);
                    }
                }
    fixed_dofs.clear();
    fixed_component.clear();
    for (const auto &[dof, c] : fixed)
      {
        fixed_dofs.push_back(dof);
        fixed_component.push_back(c);
      }
    fixed_velocity.clear();

    // Support point and component of every owned dof (affine velocity).
    {
      std::map<types::global_dof_index, Point<dim>> support;
      DoFTools::map_dofs_to_support_points(mapping, dof_handler, support);
      std::vector<IndexSet> by_component(dim);
      for (unsigned int c = 0; c < dim; ++c)
        {
          ComponentMask mask(dim, false);
          mask.set(c, true);
          by_component[c] = DoFTools::extract_dofs(dof_handler, mask);
        }
      dof_point.clear();
      dof_component.clear();
      for (const auto i : owned)
        {
          dof_point.push_back(support.at(i));
          unsigned char c = 0;
          while (c + 1 < dim && !by_component[c].is_element(i))
            ++c;
          dof_component.push_back(c);
        }
      has_affine  = false;
      affine_rate = Tensor<2, dim>();
    }

    // Interface vertices owned by this rank.
    iface_points.clear();
    iface_dofs.clear();
    std::set<unsigned int> seen;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial()) // see the ghost-cell note above
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == boundary_id::interface)
            for (const unsigned int vtx : face->vertex_indices())
              if (owned.is_element(face->vertex_dof_index(vtx, 0)) &&
                  seen.insert(face->vertex_index(vtx)).second)
                {
                  iface_points.push_back(face->vertex(vtx));
                  std::array<types::global_dof_index, dim> d;
                  for (unsigned int c = 0; c < dim; ++c)
                    d[c] = face->vertex_dof_index(vtx, c);
                  iface_dofs.push_back(d);
                }
    current_time = 0;
  }

  template <int dim>
  void ExplicitDynamics<dim>::set_coupling_vertices(const std::vector<Point<dim>> &points)
  {
    AssertThrow(settings.degree == 1,
                ExcMessage("set_coupling_vertices: degree 1 elements only"));
    // Vertex -> (point, dofs) of the locally owned vertices, then a lookup
    // per requested point (closest vertex; exact up to round-off).
    std::map<unsigned int,
             std::pair<Point<dim>, std::array<types::global_dof_index, dim>>>
           vertices;
    double hmin = HUGE_VAL;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          hmin = std::min(hmin, cell->minimum_vertex_distance());
          for (const unsigned int v : cell->vertex_indices())
            if (owned.is_element(cell->vertex_dof_index(v, 0)))
              {
                std::array<types::global_dof_index, dim> d;
                for (unsigned int c = 0; c < dim; ++c)
                  d[c] = cell->vertex_dof_index(v, c);
                vertices.emplace(cell->vertex_index(v),
                                 std::make_pair(cell->vertex(v), d));
              }
        }
    iface_points.clear();
    iface_dofs.clear();
    for (const auto &p : points)
      {
        double best = HUGE_VAL;
        const std::pair<Point<dim>, std::array<types::global_dof_index, dim>> *hit =
            nullptr;
        for (const auto &[index, entry] : vertices)
          if (const double d = entry.first.distance(p); d < best)
            {
              best = d;
              hit  = &entry;
            }
        if (hit == nullptr || best > 1e-9 * hmin)
          throw std::runtime_error("set_coupling_vertices: no mesh vertex at the given "
                                   "point (closest at distance " +
                                   std::to_string(best) + " m)");
        iface_points.push_back(hit->first);
        iface_dofs.push_back(hit->second);
      }
    f_ext = 0;
  }

  template <int dim>
  void ExplicitDynamics<dim>::set_mass_scaling(const double scaling)
  {
    AssertThrow(scaling > 0 && std::isfinite(scaling),
                ExcMessage("mass scaling must be > 0"));
    mass *= scaling / settings.mass_scaling;
    settings.mass_scaling = scaling;
  }

  template <int dim>
  double ExplicitDynamics<dim>::critical_time_step() const
  {
    std::set<types::global_dof_index> fixed(fixed_dofs.begin(), fixed_dofs.end());
    double                            omega2 = 0;
    for (const auto row : owned)
      {
        if (fixed.count(row))
          continue;
        double sum = 0;
        for (auto it = stiffness.begin(row); it != stiffness.end(row); ++it)
          sum += std::abs(it->value());
        omega2 = std::max(omega2, sum / mass(row));
      }
    omega2 = Utilities::MPI::max(omega2, comm);
    return 2.0 / std::sqrt(omega2);
  }

  template <int dim>
  void ExplicitDynamics<dim>::set_interface_forces(
      const std::vector<Tensor<1, dim>> &forces)
  {
    AssertThrow(forces.size() == iface_dofs.size(),
                ExcMessage("set_interface_forces: got " + std::to_string(forces.size()) +
                           " forces for " + std::to_string(iface_dofs.size()) +
                           " interface vertices"));
    f_ext = 0;
    for (std::size_t k = 0; k < forces.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        f_ext(iface_dofs[k][c]) = forces[k][c];
    f_ext.compress(VectorOperation::insert);
  }

  template <int dim>
  void ExplicitDynamics<dim>::step(const double dt)
  {
    AssertThrow(dt > 0, ExcMessage("time step must be > 0"));
    stiffness.vmult(work, u); // internal force K u
    const double a  = settings.damping;
    const double c1 = 1 - 0.5 * a * dt, c2 = 1.0 / (1 + 0.5 * a * dt);
    for (const auto i : owned)
      {
        const double acc =
            (f_ext(i) + boundary_factor * f_boundary(i) - work(i)) / mass(i);
        v(i) = kinematic ? 0.0 : (c1 * v(i) + dt * acc) * c2;
      }
    for (std::size_t k = 0; k < fixed_dofs.size(); ++k)
      v(fixed_dofs[k]) = fixed_velocity.empty() ? 0.0 : fixed_velocity[k];
    v.compress(VectorOperation::insert);
    if (!has_affine)
      u.add(dt, v);
    else
      {
        std::size_t k = 0;
        for (const auto i : owned)
          u(i) += dt * (v(i) + affine_velocity(k++));
        u.compress(VectorOperation::insert);
      }
    current_time += dt;
  }

  template <int dim>
  void ExplicitDynamics<dim>::set_affine_velocity(const Tensor<2, dim> &L)
  {
    affine_rate = L;
    has_affine  = L.norm() != 0;
  }

  template <int dim>
  double ExplicitDynamics<dim>::affine_velocity(const std::size_t k) const
  {
    const unsigned int c = dof_component[k];
    double             a = 0;
    for (unsigned int j = 0; j < dim; ++j)
      a += affine_rate[c][j] * dof_point[k][j];
    return a;
  }

  template <int dim>
  void ExplicitDynamics<dim>::set_boundary_traction_load(const types::boundary_id id,
                                                         const Tensor<2, dim>    &sigma)
  {
    // f_i = int_Gamma phi_i . (sigma n) dA over the faces of id `id`.
    f_boundary = 0;
    Tensor<1, dim>                       sum;
    const QGauss<dim - 1>                quadrature(fe.degree + 1);
    FEFaceValues<dim>                    fv(mapping, fe, quadrature,
                                            update_values | update_normal_vectors | update_JxW_values);
    const unsigned int                   n = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index> dofs(n);
    Vector<double>                       cell_f(n);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == id)
            {
              fv.reinit(cell, face);
              cell_f = 0;
              for (const unsigned int q : fv.quadrature_point_indices())
                {
                  const Tensor<1, dim> traction = sigma * fv.normal_vector(q);
                  for (unsigned int i = 0; i < n; ++i)
                    {
                      const unsigned int c = fe.system_to_component_index(i).first;
                      cell_f(i) += fv.shape_value(i, q) * traction[c] * fv.JxW(q);
                    }
                }
              cell->get_dof_indices(dofs);
              for (unsigned int i = 0; i < n; ++i)
                {
                  f_boundary(dofs[i]) += cell_f(i);
                  sum[fe.system_to_component_index(i).first] += cell_f(i);
                }
            }
    f_boundary.compress(VectorOperation::add);
    boundary_sum = Utilities::MPI::sum(sum, comm);
  }

  template <int dim>
  std::vector<Tensor<1, dim>> ExplicitDynamics<dim>::interface_displacements() const
  {
    std::vector<Tensor<1, dim>> r(iface_dofs.size());
    for (std::size_t k = 0; k < r.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        r[k][c] = u(iface_dofs[k][c]);
    return r;
  }

  template <int dim>
  std::vector<double> ExplicitDynamics<dim>::interface_masses() const
  {
    std::vector<double> r(iface_dofs.size(), HUGE_VAL);
    for (std::size_t k = 0; k < r.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        r[k] = std::min<double>(r[k], mass(iface_dofs[k][c]));
    return r;
  }

  template <int dim>
  std::vector<Tensor<1, dim>> ExplicitDynamics<dim>::interface_forces() const
  {
    std::vector<Tensor<1, dim>> r(iface_dofs.size());
    for (std::size_t k = 0; k < r.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        r[k][c] = f_ext(iface_dofs[k][c]);
    return r;
  }

  template <int dim>
  std::vector<Tensor<1, dim>> ExplicitDynamics<dim>::interface_velocities() const
  {
    std::vector<Tensor<1, dim>> r(iface_dofs.size());
    for (std::size_t k = 0; k < r.size(); ++k)
      {
        for (unsigned int c = 0; c < dim; ++c)
          r[k][c] = v(iface_dofs[k][c]);
        if (has_affine)
          r[k] += affine_rate * iface_points[k];
      }
    return r;
  }

  template <int dim>
  void ExplicitDynamics<dim>::set_fixed_velocity(
      const std::function<Tensor<1, dim>(const Point<dim> &)> &vel)
  {
    std::map<types::global_dof_index, Point<dim>> support;
    DoFTools::map_dofs_to_support_points(mapping, dof_handler, support);
    fixed_velocity.assign(fixed_dofs.size(), 0.0);
    for (std::size_t k = 0; k < fixed_dofs.size(); ++k)
      {
        const auto it = support.find(fixed_dofs[k]);
        AssertThrow(it != support.end(), ExcMessage("fixed dof without support point"));
        fixed_velocity[k] = vel(it->second)[fixed_component[k]];
      }
  }

  template <int dim>
  Tensor<1, dim> ExplicitDynamics<dim>::interface_force_sum() const
  {
    Tensor<1, dim> sum;
    for (const auto &d : iface_dofs)
      for (unsigned int c = 0; c < dim; ++c)
        sum[c] += f_ext(d[c]);
    for (unsigned int c = 0; c < dim; ++c)
      sum[c] = Utilities::MPI::sum(sum[c], comm);
    return sum;
  }

  template <int dim>
  double ExplicitDynamics<dim>::kinetic_energy() const
  {
    double e = 0;
    for (const auto i : owned)
      e += 0.5 * mass(i) * v(i) * v(i);
    return Utilities::MPI::sum(e, comm);
  }

  template <int dim>
  double ExplicitDynamics<dim>::unbalanced_force_ratio() const
  {
    TrilinosWrappers::MPI::Vector ku(u);
    stiffness.vmult(ku, u);
    // The reactions of the fixed dofs balance whatever reaches them: they
    // are not part of the residual.
    std::vector<bool> fixed(owned.n_elements(), false);
    for (const auto d : fixed_dofs)
      fixed[owned.index_within_set(d)] = true;
    double r2 = 0, f2 = 0;
    std::size_t k = 0;
    for (const auto i : owned)
      if (!fixed[k++])
        {
          const double r = f_ext(i) + boundary_factor * f_boundary(i) - ku(i);
          r2 += r * r;
          f2 += ku(i) * ku(i);
        }
    r2 = Utilities::MPI::sum(r2, comm);
    f2 = Utilities::MPI::sum(f2, comm);
    return f2 > 0 ? std::sqrt(r2 / f2) : 0.0;
  }

  template <int dim>
  std::vector<double> ExplicitDynamics<dim>::save_state() const
  {
    AssertThrow(Utilities::MPI::n_mpi_processes(comm) == 1,
                ExcMessage("continuum checkpoints are implemented for serial runs only"));
    std::vector<double> s;
    s.reserve(3 * owned.n_elements() + fixed_velocity.size() + 2);
    s.push_back(current_time);
    s.push_back(double(fixed_velocity.size()));
    for (const auto *vec : {&u, &v, &f_ext})
      for (const auto i : owned)
        s.push_back((*vec)(i));
    s.insert(s.end(), fixed_velocity.begin(), fixed_velocity.end());
    return s;
  }

  template <int dim>
  void ExplicitDynamics<dim>::load_state(const std::vector<double> &s)
  {
    AssertThrow(Utilities::MPI::n_mpi_processes(comm) == 1,
                ExcMessage("continuum checkpoints are implemented for serial runs only"));
    const std::size_t n = owned.n_elements();
    if (s.size() < 2 || s.size() != 2 + 3 * n + std::size_t(s[1]))
      throw std::runtime_error("continuum checkpoint: " + std::to_string(s.size()) +
                               " values do not match " + std::to_string(n) +
                               " degrees of freedom");
    current_time  = s[0];
    std::size_t k = 2;
    for (auto *vec : {&u, &v, &f_ext})
      {
        for (const auto i : owned)
          (*vec)(i) = s[k++];
        vec->compress(VectorOperation::insert);
      }
    fixed_velocity.assign(s.begin() + k, s.end());
  }

  template class ExplicitDynamics<2>;
  template class ExplicitDynamics<3>;
} // namespace demfem::fem
