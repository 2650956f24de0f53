// Stress recovery at vertices, VTK output and the gathered wall results of
// ElasticProblem (split from elastic_problem.cc to keep files short).
#include <deal.II/base/quadrature.h>
#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>

#include "common/atomic_file.h"
#include "fem/elastic_problem.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

namespace demfem::fem
{
  using namespace dealii;
  using internal::voigt;

  template <int dim>
  void ElasticProblem<dim>::recover_stress()
  {
    TimerOutput::Scope t(*timer, "stress recovery");
    stress_dof_handler.distribute_dofs(stress_fe);
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(stress_dof_handler, relevant);
    vertex_stress.reinit(stress_dof_handler.locally_owned_dofs(), relevant, comm);
    LinearAlgebra::distributed::Vector<double> count(vertex_stress);

    // Evaluate the (discontinuous) cell stress at the cell's vertices and
    // average over the cells sharing a vertex.
    std::vector<Point<dim>> points;
    for (const unsigned int v : GeometryInfo<dim>::vertex_indices())
      points.push_back(GeometryInfo<dim>::unit_cell_vertex(v));
    const Quadrature<dim> vertex_quadrature(points);
    FEValues<dim>         fe_values(*mapping, fe, vertex_quadrature, update_gradients);
    const FEValuesExtractors::Vector     u(0);
    std::vector<SymmetricTensor<2, dim>> eps(points.size());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          fe_values[u].get_function_symmetric_gradients(solution, eps);
          const typename DoFHandler<dim>::active_cell_iterator scell(
              &triangulation, cell->level(), cell->index(), &stress_dof_handler);
          for (const unsigned int v : cell->vertex_indices())
            {
              SymmetricTensor<2, 3> e3;
              for (unsigned int i = 0; i < dim; ++i)
                for (unsigned int j = i; j < dim; ++j)
                  e3[i][j] = eps[v][i][j];
              const SymmetricTensor<2, 3> s =
                  lambda * trace(e3) * unit_symmetric_tensor<3>() + 2 * mu * e3;
              for (unsigned int k = 0; k < 6; ++k)
                {
                  const auto idx = scell->vertex_dof_index(v, k);
                  vertex_stress(idx) += s[voigt[k][0]][voigt[k][1]];
                  count(idx) += 1;
                }
            }
        }
    vertex_stress.compress(VectorOperation::add);
    count.compress(VectorOperation::add);
    for (const auto i : vertex_stress.locally_owned_elements())
      if (count(i) > 0)
        vertex_stress(i) /= count(i);
    vertex_stress.update_ghost_values();
  }

  template <int dim>
  void ElasticProblem<dim>::output_results(const unsigned int stage,
                                           const double       fraction)
  {
    TimerOutput::Scope t(*timer, "output");
    // Scaled induced displacement and total vertex stress of this stage.
    TrilinosWrappers::MPI::Vector owned(locally_owned_dofs, comm);
    owned = solution;
    owned *= fraction;
    TrilinosWrappers::MPI::Vector displacement(locally_owned_dofs, locally_relevant_dofs,
                                               comm);
    displacement = owned;

    LinearAlgebra::distributed::Vector<double> stress;
    stress.reinit(vertex_stress);
    for (const auto &cell : stress_dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          {
            if (!stress.locally_owned_elements().is_element(cell->vertex_dof_index(v, 0)))
              continue;
            SymmetricTensor<2, 3> s = sigma0_3d;
            for (unsigned int k = 0; k < 6; ++k)
              s[voigt[k][0]][voigt[k][1]] +=
                  fraction * vertex_stress(cell->vertex_dof_index(v, k));
            const auto p = principal_stresses(s);
            for (unsigned int k = 0; k < 6; ++k)
              stress(cell->vertex_dof_index(v, k)) = s[voigt[k][0]][voigt[k][1]];
            for (unsigned int k = 0; k < 3; ++k)
              stress(cell->vertex_dof_index(v, 6 + k)) = p[k];
          }
    stress.update_ghost_values();

    DataOut<dim> data_out;
    data_out.attach_dof_handler(dof_handler);
    data_out.add_data_vector(
        displacement, std::vector<std::string>(dim, "displacement"),
        DataOut<dim>::type_automatic,
        std::vector<DataComponentInterpretation::DataComponentInterpretation>(
            dim, DataComponentInterpretation::component_is_part_of_vector));
    data_out.add_data_vector(
        stress_dof_handler, stress,
        std::vector<std::string>{"stress_xx", "stress_yy", "stress_zz", "stress_xy",
                                 "stress_xz", "stress_yz", "principal_stress_1",
                                 "principal_stress_2", "principal_stress_3"});
    Vector<float> subdomain(triangulation.n_active_cells());
    subdomain = triangulation.locally_owned_subdomain();
    data_out.add_data_vector(subdomain, "subdomain");
    data_out.build_patches(*mapping, settings.degree);
    const std::string name = data_out.write_vtu_with_pvtu_record(
        settings.output_directory + "/", "solution", stage, comm, 4);
    pvd_records.emplace_back(fraction, name);
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::ostringstream pvd;
        pvd << std::setprecision(17);
        DataOutBase::write_pvd_record(pvd, pvd_records);
        write_file_atomically(settings.output_directory + "/solution.pvd", pvd.str());
      }
  }

  template <int dim>
  std::vector<WallVertex> ElasticProblem<dim>::wall_results() const
  {
    std::vector<double>    flat;
    std::set<unsigned int> seen;
    // Ghost cells too: a wall vertex may be owned by this rank while both
    // wall faces touching it belong to cells of another rank.
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() == boundary_id::tunnel_wall)
            {
              const auto                                           face = cell->face(f);
              const typename DoFHandler<dim>::active_cell_iterator scell(
                  &triangulation, cell->level(), cell->index(), &stress_dof_handler);
              const auto sface = scell->face(f);
              for (const unsigned int v : face->vertex_indices())
                {
                  const auto dof0 = face->vertex_dof_index(v, 0);
                  if (!locally_owned_dofs.is_element(dof0) ||
                      !seen.insert(face->vertex_index(v)).second)
                    continue;
                  const Point<dim> &p = face->vertex(v);
                  for (unsigned int d = 0; d < 3; ++d)
                    flat.push_back(d < dim ? p[d] : 0.0);
                  for (unsigned int d = 0; d < 3; ++d)
                    flat.push_back(d < dim ? solution(face->vertex_dof_index(v, d))
                                           : 0.0);
                  for (unsigned int k = 0; k < 6; ++k)
                    flat.push_back(sigma0_3d[voigt[k][0]][voigt[k][1]] +
                                   vertex_stress(sface->vertex_dof_index(v, k)));
                }
            }
    std::vector<WallVertex> result;
    for (const auto &part : Utilities::MPI::all_gather(comm, flat))
      for (std::size_t i = 0; i + 12 <= part.size(); i += 12)
        {
          WallVertex w;
          for (unsigned int d = 0; d < 3; ++d)
            {
              w.x[d] = part[i + d];
              w.u[d] = part[i + 3 + d];
            }
          for (unsigned int k = 0; k < 6; ++k)
            w.stress[voigt[k][0]][voigt[k][1]] = part[i + 6 + k];
          result.push_back(w);
        }
    const auto angle = [](const WallVertex &w) {
      const double a = std::atan2(w.x[1], w.x[0]);
      return a < 0 ? a + 2 * numbers::PI : a;
    };
    std::sort(result.begin(), result.end(),
              [&](const WallVertex &a, const WallVertex &b) {
                const double da = angle(a), db = angle(b);
                if (std::abs(da - db) > 1e-12)
                  return da < db;
                return a.x[2] < b.x[2];
              });
    return result;
  }

  template void ElasticProblem<2>::recover_stress();
  template void ElasticProblem<3>::recover_stress();
  template void ElasticProblem<2>::output_results(unsigned int, double);
  template void ElasticProblem<3>::output_results(unsigned int, double);
  template std::vector<WallVertex> ElasticProblem<2>::wall_results() const;
  template std::vector<WallVertex> ElasticProblem<3>::wall_results() const;
} // namespace demfem::fem
