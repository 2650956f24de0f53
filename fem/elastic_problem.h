// Linear elastic continuum around a tunnel (docs/architecture.md, "The
// continuum"): dim 2 is plane strain, dim 3 full 3D. Tension positive, SI
// units.
//
// Formulation. The medium starts in a uniform in-situ stress sigma0 with zero
// displacement. Excavation releases the traction sigma0.n that the removed
// rock exerted on the tunnel wall (boundary id 3). By linearity the
// excavation-induced field (u, dsigma) solves the elasticity problem with
//   t = -sigma0.n on the wall (n = outward normal of the solid),
//   t = 0 (unchanged far-field traction) on the far field (id 1),
//   u_z = 0 on roller faces (id 4, 3D plane-strain slab),
// and the total stress is sigma0 + dsigma. Stage k of n releases the
// fraction k/n. Rigid-body motions of this pure-traction problem are removed
// by tangential pins at the extreme far-field points (exact for in-situ
// stresses aligned with x and y, which keep these points on their axes).
#ifndef DEMFEM_FEM_ELASTIC_PROBLEM_H
#define DEMFEM_FEM_ELASTIC_PROBLEM_H

#include <deal.II/base/function.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include "fem/mesh.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace demfem::fem
{
  namespace internal
  {
    // Components of a 3x3 symmetric tensor in output order:
    // xx, yy, zz, xy, xz, yz.
    inline constexpr unsigned int voigt[6][2] = {{0, 0}, {1, 1}, {2, 2},
                                                 {0, 1}, {0, 2}, {1, 2}};
  } // namespace internal

  struct ElasticSettings
  {
    unsigned int dimension        = 2;
    std::string  output_directory = "out/fem";
    double       radius           = 1.0;
    // In-situ stress, tension positive [Pa].
    double       sxx = 0, syy = 0, szz = 0, sxy = 0, sxz = 0, syz = 0;
    unsigned int excavation_stages = 1;
    std::string  mesh              = "generate";
    double       outer_radius      = 30.0;
    double       young_modulus     = 69e9;
    double       poisson_ratio     = 0.26;
    unsigned int degree            = 2;
    unsigned int refinements       = 0;
    std::string  solver            = "amg-cg"; // or "direct"
    // Generated mesh (not in the .prm; tests use smaller meshes).
    unsigned int cells_around      = 32;
    double       slab_thickness    = 1.0;
    unsigned int slab_layers       = 1;
    bool         plane_strain_slab = true;
    // Relative residual reduction of CG.
    double solver_tolerance = 1e-12;
    bool   write_output     = true;
    bool   verbose          = true;

    dealii::SymmetricTensor<2, 3> in_situ_stress() const;
  };

  /** Results at one vertex of the tunnel wall (always 3 components). */
  struct WallVertex
  {
    dealii::Point<3>              x;
    dealii::Tensor<1, 3>          u;      // excavation-induced displacement
    dealii::SymmetricTensor<2, 3> stress; // total stress
  };

  template <int dim>
  class ElasticProblem
  {
  public:
    ElasticProblem(const ElasticSettings &settings, MPI_Comm comm);
    ~ElasticProblem();

    /** Build or read the mesh and check its boundary ids. */
    void make_grid();
    void setup_system();
    /** Stiffness matrix and the excavation load (wall release). */
    void assemble_system();
    /** Returns the number of iterations (1 for the direct solver). */
    unsigned int solve();
    /** Vertex-averaged cell stresses of the induced field. */
    void recover_stress();
    /** VTK of stage @p stage (release fraction @p fraction). */
    void output_results(unsigned int stage, double fraction);
    /** Everything above plus the files of the output directory. */
    void run();

    /**
     * Optional far-field traction change on boundary id 1 as a function of
     * position and outward normal (default: none). Verification uses the
     * exact Kirsch tractions here to remove the truncation error of the
     * finite domain.
     */
    void set_far_field_traction(
        std::function<dealii::Tensor<1, dim>(const dealii::Point<dim> &,
                                             const dealii::Tensor<1, dim> &)>
            f);

    /**
     * Patch test: solve the pre-excavation state (traction sigma0.n on ids 1
     * and 3) and return max |sigma_h - sigma0| / max|sigma0| over all
     * quadrature points, on the components the boundary conditions leave
     * free (in-plane in 2D and for roller slabs).
     */
    double in_situ_patch_error();

    /** L2 norm of (u_h - u_exact) of the induced field. */
    double l2_error(const dealii::Function<dim> &exact) const;
    /** L2 norm of the exact field (for relative errors). */
    double l2_norm(const dealii::Function<dim> &exact) const;

    /** Wall vertices (all ranks), sorted by angle then z, full release. */
    std::vector<WallVertex> wall_results() const;

    dealii::types::global_dof_index n_dofs() const { return dof_handler.n_dofs(); }
    unsigned int n_cells() const { return triangulation.n_global_active_cells(); }
    unsigned int solver_iterations() const { return last_iterations; }

  private:
    void assemble_rhs(bool in_situ_state);
    void pin_rigid_body_modes();

    ElasticSettings settings;
    MPI_Comm        comm;

    dealii::parallel::distributed::Triangulation<dim> triangulation;
    std::unique_ptr<dealii::MappingQ<dim>>            mapping;
    dealii::FESystem<dim>                             fe;
    dealii::DoFHandler<dim>                           dof_handler;
    dealii::IndexSet                                  locally_owned_dofs;
    dealii::IndexSet                                  locally_relevant_dofs;
    dealii::AffineConstraints<double>                 constraints;

    dealii::TrilinosWrappers::SparseMatrix system_matrix;
    dealii::TrilinosWrappers::MPI::Vector  system_rhs;
    dealii::TrilinosWrappers::MPI::Vector  solution; // ghosted, induced

    // Vertex stress: FE_Q(1)^6 (xx, yy, zz, xy, xz, yz) of the induced field.
    dealii::FESystem<dim>                              stress_fe;
    dealii::DoFHandler<dim>                            stress_dof_handler;
    dealii::LinearAlgebra::distributed::Vector<double> vertex_stress;

    dealii::SymmetricTensor<2, dim> sigma0;    // in-plane/3D part
    dealii::SymmetricTensor<2, 3>   sigma0_3d; // full tensor
    double                          lambda, mu;
    std::function<dealii::Tensor<1, dim>(const dealii::Point<dim> &,
                                         const dealii::Tensor<1, dim> &)>
                 far_field_traction;
    unsigned int last_iterations = 0;
    bool         has_roller      = false;

    std::vector<std::pair<double, std::string>> pvd_records;
    dealii::ConditionalOStream                  pcout;
    // Created once the mesh is valid: a TimerOutput destroyed during the
    // unwinding of an input error would print a deadlock warning.
    std::unique_ptr<dealii::TimerOutput> timer;
  };

  /** Principal stresses, largest (most tensile) first. */
  std::array<double, 3> principal_stresses(const dealii::SymmetricTensor<2, 3> &s);

} // namespace demfem::fem

#endif
