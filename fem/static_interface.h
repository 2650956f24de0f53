// Static response of the elastic continuum at the coupling vertices, for the
// quasi-static coupling scheme (docs/architecture.md, "Time schemes"): the
// continuum responds through a precomputed interface flexibility or periodic
// static solves, with a relaxation factor.
//
// Problem (linear elasticity, Q_p, plane strain in 2D, tension positive):
//   K u = f                         on the free dofs,
//   u   = lambda eps0 x             on the constrained dofs,
// where f holds nodal forces [N] at the coupling vertices only, eps0 is a
// dim x dim strain and lambda a load factor. The constrained dofs are those
// of StaticSettings::fixed (default: every component on the far field, id 1);
// every constrained component c takes component c of lambda eps0 x at its
// support point, exactly as ExplicitDynamics::set_fixed_velocity moves its
// fixed dofs (so a far-field ramp of the explicit scheme and this class
// describe the same boundary condition; on a z-roller face of a plane-strain
// slab (eps0 x)_z = 0).
//
// Method. K is assembled once with the same FE, mapping and quadrature as
// ExplicitDynamics (so both discretizations have the identical stiffness
// matrix and the explicit scheme at rest reaches exactly this solution). The
// condensed matrix A (rows and columns of constrained dofs replaced by their
// diagonal) is factorized once by a sparse direct solver (Trilinos Amesos:
// MUMPS by default, KLU optional); every later solve is one forward/backward
// substitution, the columns of F are solved in blocks of right-hand sides. The
// inhomogeneous condition is lifted: with g the vector equal to lambda eps0 x on
// constrained dofs and zero elsewhere,
//   A u = f - K g on free rows,  A_ii u_i = A_ii g_i on constrained rows.
//
// Flexibility. By linearity the coupling-vertex displacements are
//   u_c = lambda U_ff(eps0) + F f_c,
// with F = P A^-1 P^T (P picks the coupling dofs) the interface flexibility,
// computed column by column (dim n_c substitutions), symmetric (Betti) and
// positive definite when the constraints remove the rigid-body modes.
// Index of vertex k, component c in F: dim k + c. A coupling vertex may be
// partly constrained (a plane-strain slab's z-rollers): its constrained
// components have zero rows and columns in F (free_components()), F is
// positive definite on the free ones, and forces on them are ignored.
//
// MPI. On p ranks each rank passes the coupling vertices whose dofs it owns
// (as ExplicitDynamics::interface_vertices() gives them); solve() and
// far_field_response() take and return this rank's vertices. flexibility()
// is the global matrix over all ranks' vertices in rank order (rank 0's
// first), replicated on every rank; first_global_vertex() is this rank's
// offset. Amesos gathers the factorization on one rank (fine for the 2D and
// moderate 3D meshes of the coupling). Meshes with hanging nodes are refused
// (the explicit continuum does not support them either).
//
// Costs (serial, shared 2-core machine, test "[.static-bench]"; annulus
// b = 3, R = 30): 2D 128 cells around, 12288 dofs, 128 coupling vertices:
// assembly 0.05 s, MUMPS factorization 0.11 s, solve 0.01 s, F 1.5 s (KLU:
// 0.35 s, 0.014 s, 0.9 s). 3D slab 48 cells around x 6 layers, 19152 dofs,
// 336 vertices: assembly 0.35 s, MUMPS factorization 1.1 s, solve 0.03 s,
// F 33 s (672 free columns; Amesos solves one right-hand side at a time);
// KLU factorization 38 s. cost() reports the figures of a run.
#ifndef DEMFEM_FEM_STATIC_INTERFACE_H
#define DEMFEM_FEM_STATIC_INTERFACE_H

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include "fem/explicit_dynamics.h"
#include "fem/mesh.h"

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace demfem::fem
{
  struct StaticSettings
  {
    double       young_modulus = 69e9; // plane-strain continuum in 2D
    double       poisson_ratio = 0.26;
    unsigned int degree        = 1;
    // Constrained dofs: boundary id and the constrained components (size
    // dim), as ExplicitSettings::fixed. They carry u = lambda eps0 x.
    std::vector<std::pair<dealii::types::boundary_id, std::vector<bool>>> fixed = {
        {boundary_id::far_field, {true, true, true}}};
    // Amesos solver of Debian's Trilinos: "Amesos_Mumps" (multifrontal;
    // 3D slab of 19k dofs: factorization 1.1 s) or "Amesos_Klu" (no
    // supernodes: 38 s on the same slab, fine in 2D). Constraints that leave
    // a rigid-body motion free are refused before factorizing (Amesos_Mumps
    // would end the process on a singular matrix).
    std::string direct_solver = "Amesos_Mumps";

    /** Elastic constants, degree and constraints of an explicit continuum. */
    static StaticSettings from(const ExplicitSettings &explicit_settings);
  };

  /** Wall-clock costs [s] for reporting (this rank's clock). */
  struct StaticCost
  {
    double       assembly_seconds      = 0; // dofs, K, A, constrained dofs
    double       factorization_seconds = 0; // symbolic + numeric, once
    double       flexibility_seconds   = 0; // all columns of F
    double       solve_seconds_total   = 0; // solve() and far_field_response()
    double       last_solve_seconds    = 0;
    unsigned int n_solves              = 0; // excluding the columns of F
    double setup_seconds() const { return assembly_seconds + factorization_seconds; }
    double mean_solve_seconds() const
    {
      return n_solves > 0 ? solve_seconds_total / n_solves : 0.0;
    }
  };

  template <int dim>
  class StaticInterfaceResponse
  {
  public:
    /**
     * @p coupling_vertices: mesh vertices (within 1e-9 of the mesh extent)
     * whose dofs this rank owns (with degree > 1 forces still act on vertex
     * dofs only); their order is the order of every force and
     * displacement list below. A fully constrained vertex is refused (a force
     * there would do nothing).
     */
    StaticInterfaceResponse(const dealii::parallel::distributed::Triangulation<dim> &tria,
                            const StaticSettings                  &settings,
                            const std::vector<dealii::Point<dim>> &coupling_vertices);
    ~StaticInterfaceResponse();

    /** Distribute dofs, assemble K and A, factorize A (once). */
    void setup();

    /**
     * The dense interface flexibility F (global, see the header comment),
     * computed at the first call (dim n_global substitutions), then cached.
     * Collective on all ranks.
     */
    const dealii::FullMatrix<double> &flexibility();

    /** Coupling-vertex displacements for lambda = 1, no forces. Collective. */
    std::vector<dealii::Tensor<1, dim>> far_field_response(
        const dealii::Tensor<2, dim> &eps0);

    /**
     * Full static solution for load factor @p lambda, far-field strain
     * @p eps0 and nodal forces [N] at this rank's coupling vertices (same
     * order); stored in displacement(). Returns the coupling-vertex
     * displacements. Collective.
     */
    std::vector<dealii::Tensor<1, dim>> solve(
        double lambda, const dealii::Tensor<2, dim> &eps0,
        const std::vector<dealii::Tensor<1, dim>> &coupling_forces);

    /** Latest solve() result; owned entries, layout of get_dof_handler()
     *  (identical to ExplicitDynamics' on the same mesh and degree). */
    const dealii::TrilinosWrappers::MPI::Vector &displacement() const { return u; }
    const dealii::DoFHandler<dim> &get_dof_handler() const { return dof_handler; }
    const dealii::MappingQ<dim>   &get_mapping() const { return mapping; }

    const std::vector<dealii::Point<dim>> &coupling_vertices() const { return points; }
    unsigned int                           n_global_vertices() const { return n_global; }
    /** Per row of flexibility() (global order): false for a component that
     *  is constrained (e.g. u_z of a vertex on a z-roller face); its row and
     *  column of F are zero and a force on it is ignored (reaction). */
    const std::vector<bool> &free_components() const { return free_mask; }
    unsigned int             first_global_vertex() const { return first_global; }

    /** Coupling-vertex values of a vector in the layout of get_dof_handler(). */
    std::vector<dealii::Tensor<1, dim>> coupling_values(
        const dealii::TrilinosWrappers::MPI::Vector &vector) const;

    /** Sum (all ranks) of the coupling forces the latest solve() applied,
     *  constrained components excluded (what the continuum was loaded with,
     *  for the coupling's force-balance check). */
    dealii::Tensor<1, dim> applied_force_sum() const { return applied_sum; }
    /** Sum (all ranks) of the constraint reactions (K u)_i over the
     *  constrained dofs of the latest solve(): the force the far field
     *  exerts on the continuum; equilibrium makes it -applied_force_sum()
     *  (a rigid translation lies in the null space of K). Collective. */
    dealii::Tensor<1, dim> reaction_force() const;

    const StaticCost &cost() const { return costs; }

  private:
    /** x = A^-1 (rhs lifted for lambda eps0) with forces at coupling dofs. */
    void solve_into(dealii::TrilinosWrappers::MPI::Vector &x, double lambda,
                    const dealii::Tensor<2, dim>              &eps0,
                    const std::vector<dealii::Tensor<1, dim>> &forces);
    /** Throws unless the constrained dofs remove every rigid-body motion. */
    void check_rigid_body_modes() const;
    /** Dofs and free components of the coupling vertices; global count and
     *  offset. Errors agreed on by all ranks. */
    void locate_coupling_vertices();
    void check_finite(const dealii::TrilinosWrappers::MPI::Vector &x,
                      const std::string                           &what) const;

    const dealii::parallel::distributed::Triangulation<dim> &triangulation;
    StaticSettings                                           settings;
    MPI_Comm                                                 comm;
    dealii::FESystem<dim>                                    fe;
    dealii::MappingQ<dim>                                    mapping;
    dealii::DoFHandler<dim>                                  dof_handler;
    dealii::IndexSet                                         owned;

    dealii::TrilinosWrappers::SparseMatrix stiffness; // K, unconstrained
    dealii::TrilinosWrappers::SparseMatrix condensed; // A
    struct Factorization; // Amesos solver on `condensed` (static_interface.cc)
    std::unique_ptr<Factorization>        factorization;
    dealii::TrilinosWrappers::MPI::Vector u, rhs, lift, work;

    // Owned constrained dofs: index, component, support point, A_ii.
    std::vector<dealii::types::global_dof_index> fixed_dofs;
    std::vector<unsigned int>                    fixed_component;
    std::vector<dealii::Point<dim>>              fixed_point;
    std::vector<double>                          fixed_diagonal;

    std::vector<dealii::Point<dim>>                               points;
    std::vector<std::array<dealii::types::global_dof_index, dim>> vertex_dofs;
    unsigned int                                                  n_global     = 0;
    unsigned int                                                  first_global = 0;
    std::vector<bool>                                             free_mask;
    dealii::Tensor<1, dim>                                        applied_sum;

    dealii::FullMatrix<double> flexibility_matrix;
    bool                       flexibility_ready = false;
    bool                       is_set_up         = false;
    StaticCost                 costs;
  };
} // namespace demfem::fem

#endif
