#include "fem/static_interface.h"

#include "fem/isotropic_elasticity.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/vector.h>

#include <Amesos.h>
#include <Amesos_BaseSolver.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_MultiVector.h>

#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace demfem::fem
{
  using namespace dealii;

  namespace
  {
    double seconds_since(const std::chrono::steady_clock::time_point &start)
    {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
    }

    template <int dim>
    std::string format_point(const Point<dim> &p)
    {
      std::ostringstream s;
      s.precision(10);
      s << "(";
      for (unsigned int d = 0; d < dim; ++d)
        s << (d ? ", " : "") << p[d];
      s << ")";
      return s.str();
    }
  } // namespace

  StaticSettings StaticSettings::from(const ExplicitSettings &e)
  {
    StaticSettings s;
    s.young_modulus = e.young_modulus;
    s.poisson_ratio = e.poisson_ratio;
    s.degree        = e.degree;
    s.fixed         = e.fixed;
    return s;
  }

  // Amesos used directly (not TrilinosWrappers::SolverDirect) so that the
  // columns of F are solved as blocks of right-hand sides (one MUMPS call
  // per block instead of one per column).
  template <int dim>
  struct StaticInterfaceResponse<dim>::Factorization
  {
    Epetra_LinearProblem               problem;
    std::unique_ptr<Amesos_BaseSolver> solver;

    Factorization(const TrilinosWrappers::SparseMatrix &matrix, const std::string &type)
    {
      // Amesos takes a non-const operator but does not modify it.
      problem.SetOperator(const_cast<Epetra_CrsMatrix *>(&matrix.trilinos_matrix()));
      Amesos factory;
      AssertThrow(factory.Query(type.c_str()),
                  ExcMessage("StaticSettings: direct solver '" + type +
                             "' is not available in this Trilinos build"));
      solver.reset(factory.Create(type.c_str(), problem));
      AssertThrow(solver != nullptr,
                  ExcMessage("StaticInterfaceResponse: Amesos could not create " + type));
      check(solver->SymbolicFactorization(), "symbolic factorization");
      check(solver->NumericFactorization(), "numeric factorization");
    }

    void solve(Epetra_MultiVector &x, Epetra_MultiVector &b)
    {
      problem.SetLHS(&x);
      problem.SetRHS(&b);
      check(solver->Solve(), "solve");
    }

    static void check(const int code, const std::string &what)
    {
      AssertThrow(code == 0,
                  ExcMessage("StaticInterfaceResponse: Amesos " + what +
                             " failed (code " + std::to_string(code) +
                             "); a singular stiffness (do the constrained boundaries, "
                             "StaticSettings::fixed, remove every rigid-body motion?)"));
    }
  };

  template <int dim>
  StaticInterfaceResponse<dim>::StaticInterfaceResponse(
      const parallel::distributed::Triangulation<dim> &tria, const StaticSettings &s,
      const std::vector<Point<dim>> &coupling_vertices)
      : triangulation(tria)
      , settings(s)
      , comm(tria.get_communicator())
      , fe(FE_Q<dim>(std::max(1u, s.degree)), dim)
      , mapping(std::max(1u, s.degree))
      , dof_handler(tria)
      , points(coupling_vertices)
  {
    AssertThrow(s.young_modulus > 0 && std::isfinite(s.young_modulus),
                ExcMessage("StaticSettings: young modulus must be > 0, got " +
                           std::to_string(s.young_modulus)));
    AssertThrow(s.poisson_ratio > -1 && s.poisson_ratio < 0.5,
                ExcMessage("StaticSettings: poisson ratio must lie in (-1, 0.5), got " +
                           std::to_string(s.poisson_ratio)));
    AssertThrow(s.degree >= 1,
                ExcMessage("StaticSettings: degree must be >= 1 (coupling vertices "
                           "carry vertex dofs)"));
    AssertThrow(s.direct_solver == "Amesos_Klu" || s.direct_solver == "Amesos_Mumps",
                ExcMessage("StaticSettings: direct solver '" + s.direct_solver +
                           "' not available; allowed: Amesos_Klu, Amesos_Mumps"));
  }

  template <int dim>
  StaticInterfaceResponse<dim>::~StaticInterfaceResponse()
  {
    // The factorization refers to the matrix: release it first.
    factorization.reset();
    dof_handler.clear();
  }

  template <int dim>
  void StaticInterfaceResponse<dim>::setup()
  {
    const auto start = std::chrono::steady_clock::now();
    AssertThrow(!triangulation.has_hanging_nodes(),
                ExcMessage("StaticInterfaceResponse: the mesh has hanging nodes; "
                           "refine it globally (the explicit continuum does not "
                           "support them either)"));
    dof_handler.distribute_dofs(fe);
    owned = dof_handler.locally_owned_dofs();
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);

    // Constrained dofs of every non-artificial cell (ghost cells included:
    // an owned dof may lie only on boundary faces of another rank's cells,
    // and owned cells may touch constrained dofs owned elsewhere). Support
    // points through the same mapping as ExplicitDynamics::set_fixed_velocity.
    std::map<types::global_dof_index, std::pair<unsigned int, Point<dim>>> fixed;
    {
      const Quadrature<dim> support(fe.get_unit_support_points());
      FEValues<dim> support_values(mapping, fe, support, update_quadrature_points);
      std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (!cell->is_artificial())
          {
            bool reinitialized = false;
            for (const unsigned int f : cell->face_indices())
              if (cell->face(f)->at_boundary())
                for (const auto &[id, comps] : settings.fixed)
                  if (cell->face(f)->boundary_id() == id)
                    {
                      if (!reinitialized)
                        {
                          support_values.reinit(cell);
                          cell->get_dof_indices(dofs);
                          reinitialized = true;
                        }
                      for (unsigned int i = 0; i < dofs.size(); ++i)
                        {
                          const unsigned int c = fe.system_to_component_index(i).first;
                          if (c < comps.size() && comps[c] &&
                              fe.has_support_on_face(i, f))
                            fixed.emplace(
                                dofs[i],
                                std::make_pair(c, support_values.quadrature_point(i)));
                        }
                    }
          }
    }
    AssertThrow(Utilities::MPI::sum(fixed.size(), comm) > 0,
                ExcMessage("StaticInterfaceResponse: no constrained dof (StaticSettings::"
                           "fixed names no boundary of this mesh); the stiffness matrix "
                           "would be singular"));

    AffineConstraints<double> constraints;
    constraints.reinit(relevant);
    for (const auto &entry : fixed)
      if (relevant.is_element(entry.first))
        constraints.add_line(entry.first);
    constraints.close();

    fixed_dofs.clear();
    fixed_component.clear();
    fixed_point.clear();
    for (const auto &[dof, cp] : fixed)
      if (owned.is_element(dof))
        {
          fixed_dofs.push_back(dof);
          fixed_component.push_back(cp.first);
          fixed_point.push_back(cp.second);
        }

    check_rigid_body_modes();
    locate_coupling_vertices();

    // One sparsity pattern for K and A (A only drops entries).
    DynamicSparsityPattern dsp(relevant);
    DoFTools::make_sparsity_pattern(dof_handler, dsp);
    SparsityTools::distribute_sparsity_pattern(dsp, owned, comm, relevant);
    stiffness.reinit(owned, owned, dsp, comm);
    condensed.reinit(owned, owned, dsp, comm);
    for (auto *vec : {&u, &rhs, &lift, &work})
      vec->reinit(owned, comm);

    // Same bilinear form, FE, mapping and quadrature as ExplicitDynamics.
    const double        E = settings.young_modulus, nu = settings.poisson_ratio;
    const LameConstants elastic = lame_constants(E, nu);
    const QGauss<dim>   quadrature(fe.degree + 1);
    FEValues<dim>       fe_values(mapping, fe, quadrature,
                                  update_gradients | update_JxW_values);
    const unsigned int  n = fe.n_dofs_per_cell();
    FullMatrix<double>  cell_k(n, n);
    std::vector<types::global_dof_index> dofs(n);
    std::vector<SymmetricTensor<2, dim>> eps(n);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_k = 0;
          fe_values.reinit(cell);
          add_isotropic_stiffness(fe_values, elastic, eps, cell_k);
          cell->get_dof_indices(dofs);
          stiffness.add(dofs, cell_k);
          constraints.distribute_local_to_global(cell_k, dofs, condensed);
        }
    stiffness.compress(VectorOperation::add);
    condensed.compress(VectorOperation::add);
    fixed_diagonal.resize(fixed_dofs.size());
    for (std::size_t k = 0; k < fixed_dofs.size(); ++k)
      fixed_diagonal[k] = condensed.diag_element(fixed_dofs[k]);

    costs.assembly_seconds = seconds_since(start);

    // Factorize once (symbolic and numeric); solves reuse it.
    const auto factor_start = std::chrono::steady_clock::now();
    factorization = std::make_unique<Factorization>(condensed, settings.direct_solver);
    costs.factorization_seconds = seconds_since(factor_start);
    flexibility_ready           = false;
    is_set_up                   = true;
  }

  template <int dim>
  void StaticInterfaceResponse<dim>::check_rigid_body_modes() const
  {
    // The constraints must remove every rigid-body motion, else A is
    // singular (KLU reports it, but Amesos_Mumps ends the process on a
    // singular matrix). A combination of rigid modes (translations e_c,
    // rotations w x x) vanishing on all constrained dofs exists iff the Gram
    // matrix G = R^T R of the modes' values R at the constrained dofs is
    // singular; coordinates are scaled by their extent so that G is
    // well conditioned when it is regular.
    {
      const unsigned int n_modes = dim == 2 ? 3 : 6;
      double             scale   = 0;
      for (const auto &x : fixed_point)
        scale = std::max(scale, x.norm());
      scale                 = std::max(Utilities::MPI::max(scale, comm), 1e-300);
      const auto mode_value = [&](const unsigned int m, const unsigned int c,
                                  const Point<dim> &x_) -> double {
        const Point<dim> x = x_ / scale;
        if (m < dim)
          return m == c ? 1.0 : 0.0;
        if constexpr (dim == 2)
          return c == 0 ? -x[1] : x[0];
        else
          {
            // rotation about axis k = m - 3: (e_k x x)_c
            const unsigned int k = m - 3;
            Tensor<1, 3>       e;
            e[k] = 1;
            return cross_product_3d(e, Tensor<1, 3>(x))[c];
          }
      };
      std::vector<double> gram(n_modes * n_modes, 0.0);
      for (std::size_t k = 0; k < fixed_dofs.size(); ++k)
        for (unsigned int i = 0; i < n_modes; ++i)
          for (unsigned int j = 0; j < n_modes; ++j)
            gram[i * n_modes + j] += mode_value(i, fixed_component[k], fixed_point[k]) *
                                     mode_value(j, fixed_component[k], fixed_point[k]);
      Utilities::MPI::sum(gram, comm, gram);
      LAPACKFullMatrix<double> g(n_modes);
      for (unsigned int i = 0; i < n_modes; ++i)
        for (unsigned int j = 0; j < n_modes; ++j)
          g(i, j) = gram[i * n_modes + j];
      g.compute_eigenvalues();
      double lmin = HUGE_VAL, lmax = 0;
      for (unsigned int i = 0; i < n_modes; ++i)
        lmin = std::min(lmin, g.eigenvalue(i).real()),
        lmax = std::max(lmax, g.eigenvalue(i).real());
      AssertThrow(lmin > 1e-10 * lmax,
                  ExcMessage("StaticInterfaceResponse: the constrained boundaries "
                             "(StaticSettings::fixed) leave a rigid-body motion free "
                             "(translation or rotation); the stiffness matrix would be "
                             "singular"));
    }
  }

  template <int dim>
  void StaticInterfaceResponse<dim>::locate_coupling_vertices()
  {
    // Coupling vertices: owned mesh vertices binned on a grid much coarser
    // than the match tolerance, so that a lookup checks 3^dim bins.
    std::vector<std::pair<Point<dim>, std::array<types::global_dof_index, dim>>> owned_v;
    {
      std::set<unsigned int> seen;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (!cell->is_artificial())
          for (const unsigned int v : cell->vertex_indices())
            if (owned.is_element(cell->vertex_dof_index(v, 0)) &&
                seen.insert(cell->vertex_index(v)).second)
              {
                std::array<types::global_dof_index, dim> d;
                for (unsigned int c = 0; c < dim; ++c)
                  d[c] = cell->vertex_dof_index(v, c);
                owned_v.emplace_back(cell->vertex(v), d);
              }
    }
    double extent = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (!cell->is_artificial())
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int d = 0; d < dim; ++d)
            extent = std::max(extent, std::abs(cell->vertex(v)[d]));
    extent           = Utilities::MPI::max(extent, comm);
    const double tol = 1e-9 * extent, bin = 1e-6 * extent;
    using Key      = std::array<long long, dim>;
    const auto key = [bin](const Point<dim> &p) {
      Key k;
      for (unsigned int d = 0; d < dim; ++d)
        k[d] = static_cast<long long>(std::floor(p[d] / bin));
      return k;
    };
    std::map<Key, std::vector<std::size_t>> bins;
    for (std::size_t i = 0; i < owned_v.size(); ++i)
      bins[key(owned_v[i].first)].push_back(i);

    // Errors are agreed on by all ranks before throwing, so that no rank is
    // left waiting in a collective call.
    std::set<types::global_dof_index> fixed_set(fixed_dofs.begin(), fixed_dofs.end());
    std::set<std::size_t>             used;
    std::string                       error;
    std::vector<bool>                 local_free;
    vertex_dofs.clear();
    for (const auto &p : points)
      {
        const Key   k0    = key(p);
        std::size_t found = owned_v.size();
        for (unsigned int b = 0; b < Utilities::pow(3u, dim); ++b)
          {
            Key          k = k0;
            unsigned int r = b;
            for (unsigned int d = 0; d < dim; ++d, r /= 3)
              k[d] += static_cast<long long>(r % 3) - 1;
            const auto it = bins.find(k);
            if (it != bins.end())
              for (const auto i : it->second)
                if (owned_v[i].first.distance(p) <= tol)
                  found = i;
          }
        if (found == owned_v.size())
          error = "coupling vertex " + format_point(p) +
                  " is not a mesh vertex whose dofs this MPI rank owns (pass the points "
                  "ExplicitDynamics::interface_vertices() gives on this rank)";
        else if (!used.insert(found).second)
          error = "coupling vertex " + format_point(p) + " is listed twice";
        else
          {
            // A partly constrained vertex (e.g. on the z-roller faces of a
            // plane-strain slab) is fine: only its free components respond.
            unsigned int n_constrained = 0;
            for (unsigned int c = 0; c < dim; ++c)
              n_constrained += fixed_set.count(owned_v[found].second[c]);
            if (n_constrained == dim)
              error = "coupling vertex " + format_point(p) +
                      " lies on a fully constrained boundary (StaticSettings::fixed); "
                      "a force there would do nothing";
          }
        if (!error.empty())
          break;
        vertex_dofs.push_back(owned_v[found].second);
        for (unsigned int c = 0; c < dim; ++c)
          local_free.push_back(fixed_set.count(owned_v[found].second[c]) == 0);
      }
    const bool any_error = Utilities::MPI::max(error.empty() ? 0 : 1, comm) > 0;
    AssertThrow(!any_error,
                ExcMessage("StaticInterfaceResponse: " +
                           (error.empty() ? std::string("bad coupling vertex on another "
                                                        "MPI rank")
                                          : error)));
    const auto counts =
        Utilities::MPI::all_gather(comm, static_cast<unsigned int>(points.size()));
    const unsigned int rank = Utilities::MPI::this_mpi_process(comm);
    n_global = first_global = 0;
    for (unsigned int r = 0; r < counts.size(); ++r)
      {
        if (r < rank)
          first_global += counts[r];
        n_global += counts[r];
      }
    free_mask.clear();
    for (const auto &part : Utilities::MPI::all_gather(comm, local_free))
      free_mask.insert(free_mask.end(), part.begin(), part.end());
  }

  template <int dim>
  void StaticInterfaceResponse<dim>::check_finite(const TrilinosWrappers::MPI::Vector &x,
                                                  const std::string &what) const
  {
    const double norm = x.l2_norm();
    AssertThrow(std::isfinite(norm),
                ExcMessage("StaticInterfaceResponse: " + what +
                           " gave non-finite displacements: the condensed stiffness is "
                           "singular (do the constrained boundaries, StaticSettings::"
                           "fixed, remove every rigid-body motion?)"));
  }

  template <int dim>
  void StaticInterfaceResponse<dim>::solve_into(TrilinosWrappers::MPI::Vector     &x,
                                                const double                       lambda,
                                                const Tensor<2, dim>              &eps0,
                                                const std::vector<Tensor<1, dim>> &forces)
  {
    AssertThrow(is_set_up, ExcMessage("StaticInterfaceResponse: call setup() first"));
    AssertThrow(forces.empty() || forces.size() == points.size(),
                ExcMessage("StaticInterfaceResponse: got " +
                           std::to_string(forces.size()) + " coupling forces for " +
                           std::to_string(points.size()) + " coupling vertices"));
    AssertThrow(std::isfinite(lambda) && std::isfinite(eps0.norm()),
                ExcMessage("StaticInterfaceResponse: non-finite load factor or strain"));
    // Lift g = lambda eps0 x on the constrained dofs; rhs = f - K g there
    // replaced by A_ii g_i (header comment).
    lift = 0;
    if (lambda != 0)
      for (std::size_t k = 0; k < fixed_dofs.size(); ++k)
        lift(fixed_dofs[k]) = lambda * (eps0 * fixed_point[k])[fixed_component[k]];
    lift.compress(VectorOperation::insert);
    stiffness.vmult(rhs, lift);
    rhs *= -1.0;
    for (std::size_t k = 0; k < forces.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        rhs(vertex_dofs[k][c]) += forces[k][c];
    for (std::size_t k = 0; k < fixed_dofs.size(); ++k)
      rhs(fixed_dofs[k]) = fixed_diagonal[k] * lift(fixed_dofs[k]);
    rhs.compress(VectorOperation::insert);
    factorization->solve(x.trilinos_vector(), rhs.trilinos_vector());
    // The constrained values exactly (the solve returns them to round-off).
    for (const auto dof : fixed_dofs)
      x(dof) = lift(dof);
    x.compress(VectorOperation::insert);
  }

  template <int dim>
  std::vector<Tensor<1, dim>> StaticInterfaceResponse<dim>::coupling_values(
      const TrilinosWrappers::MPI::Vector &x) const
  {
    std::vector<Tensor<1, dim>> r(vertex_dofs.size());
    for (std::size_t k = 0; k < r.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        r[k][c] = x(vertex_dofs[k][c]);
    return r;
  }

  template <int dim>
  std::vector<Tensor<1, dim>> StaticInterfaceResponse<dim>::solve(
      const double lambda, const Tensor<2, dim> &eps0,
      const std::vector<Tensor<1, dim>> &forces)
  {
    AssertThrow(forces.size() == points.size(),
                ExcMessage("StaticInterfaceResponse::solve: got " +
                           std::to_string(forces.size()) + " coupling forces for " +
                           std::to_string(points.size()) + " coupling vertices"));
    const auto start = std::chrono::steady_clock::now();
    solve_into(u, lambda, eps0, forces);
    check_finite(u, "solve()");
    applied_sum = 0;
    for (std::size_t k = 0; k < forces.size(); ++k)
      for (unsigned int c = 0; c < dim; ++c)
        if (free_mask[dim * (first_global + k) + c])
          applied_sum[c] += forces[k][c];
    for (unsigned int c = 0; c < dim; ++c)
      applied_sum[c] = Utilities::MPI::sum(applied_sum[c], comm);
    costs.last_solve_seconds = seconds_since(start);
    costs.solve_seconds_total += costs.last_solve_seconds;
    ++costs.n_solves;
    return coupling_values(u);
  }

  template <int dim>
  Tensor<1, dim> StaticInterfaceResponse<dim>::reaction_force() const
  {
    TrilinosWrappers::MPI::Vector ku(owned, comm);
    stiffness.vmult(ku, u);
    Tensor<1, dim> sum;
    for (std::size_t k = 0; k < fixed_dofs.size(); ++k)
      sum[fixed_component[k]] += ku(fixed_dofs[k]);
    for (unsigned int c = 0; c < dim; ++c)
      sum[c] = Utilities::MPI::sum(sum[c], comm);
    return sum;
  }

  template <int dim>
  std::vector<Tensor<1, dim>> StaticInterfaceResponse<dim>::far_field_response(
      const Tensor<2, dim> &eps0)
  {
    const auto                    start = std::chrono::steady_clock::now();
    TrilinosWrappers::MPI::Vector x(owned, comm);
    solve_into(x, 1.0, eps0, {});
    check_finite(x, "far_field_response()");
    costs.last_solve_seconds = seconds_since(start);
    costs.solve_seconds_total += costs.last_solve_seconds;
    ++costs.n_solves;
    return coupling_values(x);
  }

  template <int dim>
  const FullMatrix<double> &StaticInterfaceResponse<dim>::flexibility()
  {
    AssertThrow(is_set_up, ExcMessage("StaticInterfaceResponse: call setup() first"));
    if (flexibility_ready)
      return flexibility_matrix;
    const auto         start = std::chrono::steady_clock::now();
    const unsigned int n     = dim * n_global;
    flexibility_matrix.reinit(n, n);
    // Columns j (free components only; a constrained component keeps a
    // zero row and column): unit force on global vertex j / dim, component
    // j % dim; solved in blocks of right-hand sides.
    std::vector<unsigned int> columns;
    for (unsigned int j = 0; j < n; ++j)
      if (free_mask[j])
        columns.push_back(j);
    const auto counts =
        Utilities::MPI::all_gather(comm, static_cast<unsigned int>(points.size()));
    const Epetra_CrsMatrix &A         = condensed.trilinos_matrix();
    const auto              local_row = [&](const Epetra_BlockMap        &map,
                               const types::global_dof_index dof) {
      return map.LID(static_cast<TrilinosWrappers::types::int_type>(dof));
    };
    const unsigned int block   = 64;
    const std::size_t  n_local = dim * points.size();
    for (std::size_t start = 0; start < columns.size(); start += block)
      {
        const unsigned int nb = std::min<std::size_t>(block, columns.size() - start);
        Epetra_MultiVector b(A.RangeMap(), nb), x(A.DomainMap(), nb); // zeroed
        for (unsigned int q = 0; q < nb; ++q)
          {
            const unsigned int v = columns[start + q] / dim, c = columns[start + q] % dim;
            if (v >= first_global && v < first_global + points.size())
              b[q][local_row(A.RangeMap(), vertex_dofs[v - first_global][c])] = 1.0;
          }
        factorization->solve(x, b);
        std::vector<double> local(nb * n_local);
        for (unsigned int q = 0; q < nb; ++q)
          for (std::size_t k = 0; k < points.size(); ++k)
            for (unsigned int d = 0; d < dim; ++d)
              local[q * n_local + dim * k + d] =
                  x[q][local_row(A.DomainMap(), vertex_dofs[k][d])];
        const auto   parts = Utilities::MPI::all_gather(comm, local);
        unsigned int row0  = 0; // first row of rank r's vertices
        for (unsigned int r = 0; r < parts.size(); ++r)
          {
            const std::size_t m = dim * counts[r];
            for (unsigned int q = 0; q < nb; ++q)
              for (std::size_t i = 0; i < m; ++i)
                flexibility_matrix(row0 + i, columns[start + q]) = parts[r][q * m + i];
            row0 += m;
          }
      }
    for (unsigned int i = 0; i < n; ++i)
      AssertThrow(!free_mask[i] || (std::isfinite(flexibility_matrix(i, i)) &&
                                    flexibility_matrix(i, i) > 0),
                  ExcMessage("StaticInterfaceResponse: flexibility diagonal " +
                             std::to_string(i) + " is " +
                             std::to_string(flexibility_matrix(i, i)) +
                             "; the condensed stiffness is singular or indefinite"));
    costs.flexibility_seconds = seconds_since(start);
    flexibility_ready         = true;
    return flexibility_matrix;
  }

  template class StaticInterfaceResponse<2>;
  template class StaticInterfaceResponse<3>;
} // namespace demfem::fem
