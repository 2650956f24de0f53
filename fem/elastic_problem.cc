#include "fem/elastic_problem.h"

#include "fem/isotropic_elasticity.h"

#include "common/atomic_file.h"
#include "common/json_number.h"

#include <nlohmann/json.hpp>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace demfem::fem
{
  using namespace dealii;
  using internal::voigt;

  SymmetricTensor<2, 3> ElasticSettings::in_situ_stress() const
  {
    SymmetricTensor<2, 3> s;
    s[0][0] = sxx;
    s[1][1] = syy;
    s[2][2] = szz;
    s[0][1] = sxy;
    s[0][2] = sxz;
    s[1][2] = syz;
    return s;
  }

  std::array<double, 3> principal_stresses(const SymmetricTensor<2, 3> &s)
  {
    // deal.II returns the eigenvalues in descending order.
    return eigenvalues(s);
  }

  namespace
  {

    std::string str(const double x)
    {
      std::ostringstream o;
      o << x;
      return o.str();
    }

    // Returns s after checking it, so that the constructor can validate
    // before any member with MPI-collective destructor exists.
    const ElasticSettings &check_settings(const ElasticSettings &s)
    {
      AssertThrow(s.young_modulus > 0,
                  ExcMessage("Continuum/young modulus = " + str(s.young_modulus) +
                             " is invalid: it must be > 0 (Pa)"));
      AssertThrow(s.poisson_ratio > -1.0 && s.poisson_ratio < 0.5,
                  ExcMessage("Continuum/poisson ratio = " + str(s.poisson_ratio) +
                             " is invalid: it must lie in the open interval "
                             "(-1, 0.5)"));
      AssertThrow(s.radius > 0, ExcMessage("Tunnel/radius must be > 0 (m)"));
      AssertThrow(s.degree >= 1 && s.degree <= 2,
                  ExcMessage("Continuum/element degree must be 1 or 2"));
      AssertThrow(s.solver == "amg-cg" || s.solver == "direct",
                  ExcMessage("Continuum/solver must be 'amg-cg' or 'direct'"));
      AssertThrow(s.excavation_stages >= 1,
                  ExcMessage("Tunnel/excavation stages must be >= 1"));
      AssertThrow(s.dimension == 2 || s.dimension == 3,
                  ExcMessage("Problem/dimension must be 2 or 3"));
      return s;
    }
  } // namespace

  template <int dim>
  ElasticProblem<dim>::ElasticProblem(const ElasticSettings &s, MPI_Comm comm)
      : settings(check_settings(s))
      , comm(comm)
      , triangulation(comm)
      , fe(FE_Q<dim>(std::max(1u, s.degree)), dim)
      , dof_handler(triangulation)
      , stress_fe(FE_Q<dim>(1), 9)
      , stress_dof_handler(triangulation)
      , pcout(std::cout, s.verbose && Utilities::MPI::this_mpi_process(comm) == 0)
  {
    const double E  = settings.young_modulus;
    const double nu = settings.poisson_ratio;
    lambda          = E * nu / ((1 + nu) * (1 - 2 * nu));
    mu              = E / (2 * (1 + nu));
    sigma0_3d       = settings.in_situ_stress();
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = i; j < dim; ++j)
        sigma0[i][j] = sigma0_3d[i][j];
    mapping = std::make_unique<MappingQ<dim>>(settings.degree);
  }

  template <int dim>
  ElasticProblem<dim>::~ElasticProblem()
  {
    dof_handler.clear();
    stress_dof_handler.clear();
  }

  template <int dim>
  void ElasticProblem<dim>::set_far_field_traction(
      std::function<Tensor<1, dim>(const Point<dim> &, const Tensor<1, dim> &)> f)
  {
    far_field_traction = std::move(f);
  }

  template <int dim>
  void ElasticProblem<dim>::make_grid()
  {
    const auto start = std::chrono::steady_clock::now();
    if (settings.mesh == "generate")
      {
        GeneratedMeshSettings g;
        g.radius            = settings.radius;
        g.outer_radius      = settings.outer_radius;
        g.cells_around      = settings.cells_around;
        g.thickness         = settings.slab_thickness;
        g.layers            = settings.slab_layers;
        g.plane_strain_slab = settings.plane_strain_slab;
        generate_tunnel_mesh(triangulation, g);
      }
    else
      {
        AssertThrow(
            std::filesystem::is_regular_file(settings.mesh),
            ExcMessage("Continuum/mesh: file '" + settings.mesh + "' does not exist"));
        read_gmsh_mesh(triangulation, settings.mesh);
      }
    const auto ids = coarse_boundary_ids(triangulation);
    for (const types::boundary_id id : {boundary_id::far_field, boundary_id::tunnel_wall})
      AssertThrow(ids.count(id) == 1,
                  ExcMessage("Continuum/mesh '" + settings.mesh +
                             "' has no boundary with id " + std::to_string(id) +
                             " (needed: 1 = far field, 3 = tunnel wall)"));
    has_roller = (dim == 3 && ids.count(boundary_id::roller_z) == 1);
    triangulation.refine_global(settings.refinements);
    timer = std::make_unique<TimerOutput>(
        comm, pcout, settings.verbose ? TimerOutput::summary : TimerOutput::never,
        TimerOutput::wall_times);
    pcout
        << "   mesh read/generated in "
        << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
        << " s" << std::endl;
    pcout << "   mesh: " << triangulation.n_global_active_cells()
          << " cells, boundary ids:";
    for (const auto id : ids)
      pcout << ' ' << id;
    pcout << std::endl;
  }

  template <int dim>
  void ElasticProblem<dim>::pin_rigid_body_modes()
  {
    // Candidate vertices: on far-field faces; in 3D without rollers only on
    // the lowest z level so that single points (not lines) are pinned.
    const bool   point_pins = (dim == 3 && !has_roller);
    const double inf        = std::numeric_limits<double>::infinity();
    double       zmin       = inf;
    double       ext[3]     = {-inf, -inf, -inf}; // max x, max -x, max y
    for (int pass = 0; pass < 2; ++pass)
      {
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (!cell->is_artificial())
            for (const auto &face : cell->face_iterators())
              if (face->at_boundary() && face->boundary_id() == boundary_id::far_field)
                for (const unsigned int v : face->vertex_indices())
                  {
                    const Point<dim> &p = face->vertex(v);
                    if (pass == 0)
                      {
                        if (point_pins)
                          zmin = std::min(zmin, p[dim - 1]);
                        continue;
                      }
                    if (point_pins &&
                        std::abs(p[dim - 1] - zmin) > 1e-10 * std::abs(zmin) + 1e-12)
                      continue;
                    ext[0] = std::max(ext[0], p[0]);
                    ext[1] = std::max(ext[1], -p[0]);
                    ext[2] = std::max(ext[2], p[1]);
                  }
        if (pass == 0 && point_pins)
          zmin = Utilities::MPI::min(zmin, comm);
      }
    for (double &e : ext)
      e = Utilities::MPI::max(e, comm);

    // Three tangential pins remove the in-plane rigid modes without
    // over-constraining a uniform strain field: u_y at max x and min x,
    // u_x at max y. In 3D without rollers also u_z there. Among the vertices
    // with the extreme coordinate (a whole edge for a square domain) the one
    // closest to the axis through the centre is taken, where the symmetric
    // solution has no tangential displacement.
    const double tol                = 1e-10 * std::max({1.0, ext[0], ext[1], ext[2]});
    const auto   for_each_candidate = [&](const auto &fn) {
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (!cell->is_artificial())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && face->boundary_id() == boundary_id::far_field)
              for (const unsigned int v : face->vertex_indices())
                {
                  const Point<dim> &p = face->vertex(v);
                  if (point_pins &&
                      std::abs(p[dim - 1] - zmin) > 1e-10 * std::abs(zmin) + 1e-12)
                    continue;
                  const double value[3]  = {p[0], -p[0], p[1]};
                  const double offset[3] = {std::abs(p[1]), std::abs(p[1]),
                                            std::abs(p[0])};
                  for (unsigned int k = 0; k < 3; ++k)
                    if (std::abs(value[k] - ext[k]) < tol)
                      fn(face, v, k, offset[k]);
                }
    };
    double off[3] = {inf, inf, inf};
    for_each_candidate([&](const auto &, unsigned int, unsigned int k, double o) {
      off[k] = std::min(off[k], o);
    });
    for (double &o : off)
      o = Utilities::MPI::min(o, comm);
    for_each_candidate([&](const auto &face, unsigned int v, unsigned int k, double o) {
      if (std::abs(o - off[k]) > tol)
        return;
      std::vector<unsigned int> comps = {k < 2 ? 1u : 0u};
      if (point_pins)
        comps.push_back(2);
      for (const unsigned int c : comps)
        {
          const auto dof = face->vertex_dof_index(v, c);
          if (!constraints.is_constrained(dof))
            constraints.add_line(dof);
        }
    });
  }

  template <int dim>
  void ElasticProblem<dim>::setup_system()
  {
    TimerOutput::Scope t(*timer, "setup");
    dof_handler.distribute_dofs(fe);
    locally_owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);

    constraints.clear();
    constraints.reinit(locally_relevant_dofs);
    DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    if constexpr (dim == 3)
      if (has_roller)
        VectorTools::interpolate_boundary_values(
            *mapping, dof_handler, boundary_id::roller_z,
            Functions::ZeroFunction<dim>(dim), constraints,
            fe.component_mask(FEValuesExtractors::Scalar(2)));
    pin_rigid_body_modes();
    constraints.close();

    DynamicSparsityPattern dsp(locally_relevant_dofs);
    DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
    SparsityTools::distribute_sparsity_pattern(dsp, locally_owned_dofs, comm,
                                               locally_relevant_dofs);
    system_matrix.reinit(locally_owned_dofs, locally_owned_dofs, dsp, comm);
    system_rhs.reinit(locally_owned_dofs, comm);
    solution.reinit(locally_owned_dofs, locally_relevant_dofs, comm);
    pcout << "   degrees of freedom: " << dof_handler.n_dofs() << std::endl;
  }

  template <int dim>
  void ElasticProblem<dim>::assemble_system()
  {
    TimerOutput::Scope t(*timer, "assemble matrix");
    system_matrix = 0;
    const QGauss<dim>                    quadrature(fe.degree + 1);
    FEValues<dim>                        fe_values(*mapping, fe, quadrature,
                                                   update_gradients | update_JxW_values);
    const unsigned int                   n = fe.n_dofs_per_cell();
    FullMatrix<double>                   cell_matrix(n, n);
    std::vector<types::global_dof_index> dofs(n);
    std::vector<SymmetricTensor<2, dim>> eps(n);

    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_matrix = 0;
          fe_values.reinit(cell);
          add_isotropic_stiffness(fe_values, {lambda, mu}, eps, cell_matrix);
          cell->get_dof_indices(dofs);
          constraints.distribute_local_to_global(cell_matrix, dofs, system_matrix);
        }
    system_matrix.compress(VectorOperation::add);
  }

  template <int dim>
  void ElasticProblem<dim>::assemble_rhs(const bool in_situ_state)
  {
    TimerOutput::Scope t(*timer, "assemble rhs");
    system_rhs = 0;
    const QGauss<dim - 1>                face_quadrature(fe.degree + 1);
    FEFaceValues<dim>                    fe_face_values(*mapping, fe, face_quadrature,
                                                        update_values | update_normal_vectors |
                                                            update_quadrature_points | update_JxW_values);
    const FEValuesExtractors::Vector     u(0);
    const unsigned int                   n = fe.n_dofs_per_cell();
    Vector<double>                       cell_rhs(n);
    std::vector<types::global_dof_index> dofs(n);

    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->at_boundary())
        {
          cell_rhs = 0;
          bool any = false;
          for (const auto &face : cell->face_iterators())
            {
              if (!face->at_boundary())
                continue;
              const auto id = face->boundary_id();
              // Pre-excavation state: sigma0.n on every boundary. Excavation:
              // release -sigma0.n on the wall, optional far-field change.
              const bool loaded =
                  in_situ_state ? true
                                : (id == boundary_id::tunnel_wall ||
                                   (id == boundary_id::far_field && far_field_traction));
              if (!loaded)
                continue;
              any = true;
              fe_face_values.reinit(cell, face);
              for (const unsigned int q : fe_face_values.quadrature_point_indices())
                {
                  const Tensor<1, dim> &normal = fe_face_values.normal_vector(q);
                  Tensor<1, dim>        t;
                  if (in_situ_state)
                    t = sigma0 * normal;
                  else if (id == boundary_id::tunnel_wall)
                    t = -(sigma0 * normal);
                  else
                    t = far_field_traction(fe_face_values.quadrature_point(q), normal);
                  for (unsigned int i = 0; i < n; ++i)
                    cell_rhs(i) +=
                        fe_face_values[u].value(i, q) * t * fe_face_values.JxW(q);
                }
            }
          if (!any)
            continue;
          cell->get_dof_indices(dofs);
          constraints.distribute_local_to_global(cell_rhs, dofs, system_rhs);
        }
    system_rhs.compress(VectorOperation::add);
  }

  template <int dim>
  unsigned int ElasticProblem<dim>::solve()
  {
    TimerOutput::Scope            t(*timer, "solve");
    TrilinosWrappers::MPI::Vector x(locally_owned_dofs, comm);
    const double                  rhs_norm = system_rhs.l2_norm();
    if (rhs_norm == 0)
      last_iterations = 0;
    else if (settings.solver == "direct")
      {
        SolverControl                  control(1, 0);
        TrilinosWrappers::SolverDirect direct(control);
        direct.solve(system_matrix, x, system_rhs);
        last_iterations = 1;
      }
    else
      {
        TrilinosWrappers::PreconditionAMG                 amg;
        TrilinosWrappers::PreconditionAMG::AdditionalData data;
        std::vector<std::vector<bool>>                    constant_modes;
        DoFTools::extract_constant_modes(dof_handler, ComponentMask(dim, true),
                                         constant_modes);
        data.constant_modes        = constant_modes;
        data.elliptic              = true;
        data.higher_order_elements = (fe.degree > 1);
        data.smoother_sweeps       = 2;
        data.aggregation_threshold = 0.02;
        amg.initialize(system_matrix, data);

        SolverControl control(std::max<unsigned int>(2000, dof_handler.n_dofs()),
                              settings.solver_tolerance * rhs_norm);
        TrilinosWrappers::SolverCG cg(control);
        cg.solve(system_matrix, x, system_rhs, amg);
        last_iterations = control.last_step();
      }
    constraints.distribute(x);
    solution = x;
    pcout << "   solver (" << settings.solver << "): " << last_iterations << " iterations"
          << std::endl;
    return last_iterations;
  }

  template <int dim>
  double ElasticProblem<dim>::in_situ_patch_error()
  {
    assemble_rhs(true);
    solve();
    const QGauss<dim> quadrature(fe.degree + 1);
    FEValues<dim>     fe_values(*mapping, fe, quadrature, update_gradients);
    const FEValuesExtractors::Vector     u(0);
    std::vector<SymmetricTensor<2, dim>> eps(quadrature.size());
    double                               err = 0, scale = 0;
    for (const auto &c : voigt)
      scale = std::max(scale, std::abs(sigma0_3d[c[0]][c[1]]));
    // zz is free only in 3D without rollers; in plane strain (2D or slab)
    // sigma_zz is nu (sxx + syy), not an input.
    const bool check_zz = (dim == 3 && !has_roller);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          fe_values[u].get_function_symmetric_gradients(solution, eps);
          for (const auto &e : eps)
            {
              SymmetricTensor<2, 3> e3;
              for (unsigned int i = 0; i < dim; ++i)
                for (unsigned int j = i; j < dim; ++j)
                  e3[i][j] = e[i][j];
              const SymmetricTensor<2, 3> s =
                  lambda * trace(e3) * unit_symmetric_tensor<3>() + 2 * mu * e3;
              for (unsigned int k = 0; k < 6; ++k)
                {
                  const unsigned int i = voigt[k][0], j = voigt[k][1];
                  if ((i == 2 || j == 2) && (dim == 2 || (i == 2 && j == 2 && !check_zz)))
                    continue;
                  err = std::max(err, std::abs(s[i][j] - sigma0_3d[i][j]));
                }
            }
        }
    err = Utilities::MPI::max(err, comm);
    return err / scale;
  }

  template <int dim>
  double ElasticProblem<dim>::l2_error(const Function<dim> &exact) const
  {
    Vector<float> cellwise(triangulation.n_active_cells());
    VectorTools::integrate_difference(*mapping, dof_handler, solution, exact, cellwise,
                                      QGauss<dim>(fe.degree + 2), VectorTools::L2_norm);
    return VectorTools::compute_global_error(triangulation, cellwise,
                                             VectorTools::L2_norm);
  }

  template <int dim>
  double ElasticProblem<dim>::l2_norm(const Function<dim> &exact) const
  {
    TrilinosWrappers::MPI::Vector zero(locally_owned_dofs, locally_relevant_dofs, comm);
    Vector<float>                 cellwise(triangulation.n_active_cells());
    VectorTools::integrate_difference(*mapping, dof_handler, zero, exact, cellwise,
                                      QGauss<dim>(fe.degree + 2), VectorTools::L2_norm);
    return VectorTools::compute_global_error(triangulation, cellwise,
                                             VectorTools::L2_norm);
  }

  template <int dim>
  void ElasticProblem<dim>::run()
  {
    const auto start = std::chrono::steady_clock::now();
    pcout << "demfem fem: " << dim << "D " << (dim == 2 ? "plane strain" : "")
          << ", E = " << settings.young_modulus << " Pa, nu = " << settings.poisson_ratio
          << std::endl;
    make_grid(); // validates the mesh before anything is written
    setup_system();
    assemble_system();
    assemble_rhs(false);
    solve();
    recover_stress();

    // Without output (tests) nothing is written at all.
    const bool root =
        settings.write_output && Utilities::MPI::this_mpi_process(comm) == 0;
    if (root)
      std::filesystem::create_directories(settings.output_directory);
    MPI_Barrier(comm);
    if (settings.write_output)
      for (unsigned int k = 0; k <= settings.excavation_stages; ++k)
        output_results(k, double(k) / settings.excavation_stages);

    const auto wall = wall_results();
    // Hoop stress only on the wall circle (a 3D mesh's id 3 also holds the
    // tunnel face, where the hoop direction is undefined at the axis).
    double r_wall = 0;
    for (const auto &w : wall)
      r_wall = std::max(r_wall, std::hypot(w.x[0], w.x[1]));
    // Per stage k: release fraction f, induced u scales with f, total stress
    // is sigma0 + f (sigma - sigma0).
    struct StageRecord
    {
      double fraction, max_u = 0, hoop_min = 1e300, hoop_max = -1e300;
    };
    std::vector<StageRecord> history;
    for (unsigned int k = 0; k <= settings.excavation_stages; ++k)
      {
        StageRecord h;
        h.fraction = double(k) / settings.excavation_stages;
        for (const auto &w : wall)
          {
            h.max_u        = std::max(h.max_u, h.fraction * w.u.norm());
            const double r = std::hypot(w.x[0], w.x[1]);
            if (r < (1 - 1e-6) * r_wall)
              continue;
            Tensor<1, 3> t;
            t[0]              = -w.x[1] / r;
            t[1]              = w.x[0] / r;
            const auto   sig  = sigma0_3d + h.fraction * (w.stress - sigma0_3d);
            const double hoop = t * (sig * t);
            h.hoop_min        = std::min(h.hoop_min, hoop);
            h.hoop_max        = std::max(h.hoop_max, hoop);
          }
        history.push_back(h);
      }
    const double max_u = history.back().max_u, hoop_min = history.back().hoop_min,
                 hoop_max = history.back().hoop_max;
    const double wall_time =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (root)
      {
        // Each file replaced atomically (common/atomic_file.h).
        std::ostringstream du, ds, hs;
        du << std::setprecision(12) << "x,y,z,ux,uy,uz\n";
        ds << std::setprecision(12) << "x,y,z,sxx,syy,szz,sxy,sxz,syz\n";
        for (const auto &w : wall)
          {
            du << w.x[0] << ',' << w.x[1] << ',' << w.x[2] << ',' << w.u[0] << ','
               << w.u[1] << ',' << w.u[2] << '\n';
            ds << w.x[0] << ',' << w.x[1] << ',' << w.x[2];
            for (const auto &c : voigt)
              ds << ',' << w.stress[c[0]][c[1]];
            ds << '\n';
          }
        hs << std::setprecision(12)
           << "stage,release_fraction,max_wall_displacement,min_wall_hoop_stress,"
              "max_wall_hoop_stress\n";
        for (unsigned int k = 0; k < history.size(); ++k)
          hs << k << ',' << history[k].fraction << ',' << history[k].max_u << ','
             << history[k].hoop_min << ',' << history[k].hoop_max << '\n';
        nlohmann::ordered_json j;
        j["command"]        = "fem";
        j["dim"]            = dim;
        j["plane_strain"]   = dim == 2;
        j["mesh"]           = settings.mesh;
        j["n_cells"]        = triangulation.n_global_active_cells();
        j["n_dofs"]         = dof_handler.n_dofs();
        j["element_degree"] = settings.degree;
        j["refinements"]    = settings.refinements;
        j["E"]              = json_number(settings.young_modulus);
        j["nu"]             = json_number(settings.poisson_ratio);
        j["radius"]         = json_number(settings.radius);
        j["in_situ_stress"] = {
            {"xx", json_number(settings.sxx)}, {"yy", json_number(settings.syy)},
            {"zz", json_number(settings.szz)}, {"xy", json_number(settings.sxy)},
            {"xz", json_number(settings.sxz)}, {"yz", json_number(settings.syz)}};
        j["excavation_stages"]     = settings.excavation_stages;
        j["solver"]                = settings.solver;
        j["solver_iterations"]     = last_iterations;
        j["n_ranks"]               = Utilities::MPI::n_mpi_processes(comm);
        j["n_wall_vertices"]       = wall.size();
        j["max_wall_displacement"] = json_number(max_u);
        j["min_wall_hoop_stress"]  = json_number(hoop_min);
        j["max_wall_hoop_stress"]  = json_number(hoop_max);
        j["wall_time_s"]           = json_number(wall_time);
        const std::string &dir     = settings.output_directory;
        write_file_atomically(dir + "/wall_displacement.csv", du.str());
        write_file_atomically(dir + "/wall_stress.csv", ds.str());
        write_file_atomically(dir + "/history.csv", hs.str());
        write_file_atomically(dir + "/summary.json", j.dump(2) + "\n");
      }
    pcout << "   max wall displacement: " << max_u << " m; wall hoop stress in ["
          << hoop_min << ", " << hoop_max << "] Pa" << std::endl
          << "   output: " << settings.output_directory << std::endl;
  }

  template class ElasticProblem<2>;
  template class ElasticProblem<3>;
} // namespace demfem::fem
