// Explicit-dynamic elastic continuum for the DEM coupling
// (docs/architecture.md, "The continuum" and "Coupling"): lumped (row-sum) mass
// with optional density scaling, mass-proportional damping, central-difference
// (leapfrog) stepping, external nodal forces on a set of coupling vertices (by
// default the vertices of the interface boundary, id 2; set_coupling_vertices()
// takes any mesh vertices, e.g. the nodes of the cells a slaved DEM layer
// overlaps), and queries of the coupling vertices' displacement and velocity.
//
// Scheme (velocities at half steps, damping centred in time):
//   v_{n+1/2} = [(1 - a dt/2) v_{n-1/2} + dt M^-1 (f_n - K u_n)] / (1 + a dt/2)
//   u_{n+1}   = u_n + dt v_{n+1/2}
// It is stable for dt <= 2 / omega_max; critical_time_step() returns
// 2 / sqrt(max_i sum_j |K_ij| / M_i), a Gershgorin upper bound of omega_max,
// hence a safe (slightly conservative) limit.
#ifndef DEMFEM_FEM_EXPLICIT_DYNAMICS_H
#define DEMFEM_FEM_EXPLICIT_DYNAMICS_H

#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include "fem/mesh.h"

#include <functional>
#include <memory>
#include <vector>

namespace demfem::fem
{
  struct ExplicitSettings
  {
    double       young_modulus = 69e9;
    double       poisson_ratio = 0.26;
    double       density       = 2700; // kg/m^3
    double       mass_scaling  = 1.0;  // density scaling factor (>= 1 speeds up)
    double       damping       = 0.0;  // mass-proportional coefficient a [1/s]
    unsigned int degree        = 1;
    // Zero-displacement conditions: boundary id and the constrained
    // components (size dim). Default: far field (id 1) fully fixed.
    std::vector<std::pair<dealii::types::boundary_id, std::vector<bool>>> fixed = {
        {boundary_id::far_field, {true, true, true}}};
  };

  template <int dim>
  class ExplicitDynamics
  {
  public:
    ExplicitDynamics(const dealii::parallel::distributed::Triangulation<dim> &tria,
                     const ExplicitSettings                                  &settings);
    ~ExplicitDynamics();

    /** Distribute dofs, assemble K and the lumped mass; state = rest. */
    void setup();

    /** Replaces the density scaling factor after setup(): the lumped masses
     *  are rescaled (the static response does not depend on them). */
    void set_mass_scaling(double scaling);
    /** Replaces the mass-proportional damping coefficient a [1/s]. */
    void set_damping(double a) { settings.damping = a; }
    double mass_scaling() const { return settings.mass_scaling; }
    /** Safe time step limit of the undamped central-difference scheme. */
    double critical_time_step() const;

    /** Coupling vertices whose dofs this rank owns (fixed order): after
     *  setup() the vertices on boundary id 2, or those given to
     *  set_coupling_vertices(). */
    const std::vector<dealii::Point<dim>> &interface_vertices() const
    {
      return iface_points;
    }

    /** Replaces the coupling vertices by the mesh vertices at `points` (same
     *  order; each must coincide with a mesh vertex within 1e-9 of the cell
     *  size, else std::runtime_error). Clears the held nodal forces. Degree 1
     *  only (vertex dofs are the nodes). */
    void set_coupling_vertices(const std::vector<dealii::Point<dim>> &points);

    /** Nodal forces [N] on the coupling vertices, same order; held until
     *  replaced. */
    void set_interface_forces(const std::vector<dealii::Tensor<1, dim>> &forces);

    /** Advance by dt (must not exceed critical_time_step()). */
    void step(double dt);

    std::vector<dealii::Tensor<1, dim>> interface_displacements() const;
    /** Lumped (scaled) mass of each coupling vertex's dofs [kg], same order
     *  (smallest over its components). */
    std::vector<double> interface_masses() const;
    /** Velocities at the latest half step t - dt/2. */
    std::vector<dealii::Tensor<1, dim>> interface_velocities() const;

    /** Velocity of the zero-displacement dofs from now on: each constrained
     *  dof moves with component c of v(x) at its support point (default
     *  zero). Used to ramp a far-field displacement u = eps x (in-situ
     *  loading of a coupled run). */
    void set_fixed_velocity(
        const std::function<dealii::Tensor<1, dim>(const dealii::Point<dim> &)> &v);

    /** Boundary load: the consistent nodal forces of the traction sigma.n
     *  (n the outward normal of the solid) on the faces with boundary id
     *  `id`, held apart from the coupling forces and applied scaled by
     *  set_boundary_load_factor() (default 0). A coupled tunnel section
     *  (3D) carries the in-situ traction of the rock the tunnel replaces
     *  with it, ramped with the in-situ load and released by excavation. */
    void   set_boundary_traction_load(dealii::types::boundary_id    id,
                                      const dealii::Tensor<2, dim> &sigma);
    void   set_boundary_load_factor(double factor) { boundary_factor = factor; }
    double boundary_load_factor() const { return boundary_factor; }
    /** Sum of the boundary load at factor 1 (all ranks) [N]. */
    dealii::Tensor<1, dim> boundary_load_sum() const { return boundary_sum; }
    /** Affine velocity L x added to the motion of every node from now on
     *  (u += dt (v + L x); v, the dynamic part, is unchanged; fixed dofs
     *  move with their prescribed velocity plus L x). A homogeneous strain
     *  rate applied to the whole body at once: an in-situ ramp that needs
     *  no wave to cross the mesh from the far field (a coupled tunnel
     *  section, whose tunnel-wall traction acts next to the grains). Zero
     *  by default. interface_velocities() include it. */
    void set_affine_velocity(const dealii::Tensor<2, dim> &L);
    /** While on, the dynamic velocity stays zero: the body moves only with
     *  the affine and prescribed velocities (a kinematic in-situ
     *  installation; the forces it does not follow are relaxed when it is
     *  switched off). Off by default. */
    void set_kinematic(bool on) { kinematic = on; }
    /** The nodal forces held at the coupling vertices (same order). */
    std::vector<dealii::Tensor<1, dim>> interface_forces() const;

    /** Sum over the coupling vertices of the nodal forces currently held
     *  in the external force vector (all ranks): what the continuum is
     *  actually loaded with, for the coupling's force-balance check. */
    dealii::Tensor<1, dim> interface_force_sum() const;

    double                                       kinetic_energy() const;
    /** Unbalanced-force ratio of the free dofs: |f - K u| / |K u| (2-norms
     *  over the dofs that are not fixed, f the coupling and boundary loads).
     *  The continuum's static residual, as the DEM's unbalanced ratio; 0
     *  when nothing is loaded. One matrix-vector product. */
    double                                       unbalanced_force_ratio() const;
    double                                       time() const { return current_time; }
    const dealii::TrilinosWrappers::MPI::Vector &displacement() const { return u; }
    const dealii::DoFHandler<dim> &get_dof_handler() const { return dof_handler; }

    /** Dynamic state for checkpoints (docs/architecture.md, "Checkpoints and
     *  restart"): the locally owned entries of u, v and the external forces,
     *  the fixed-dof velocities and the time, bit for bit. Serial runs only
     *  (one rank owns every dof). */
    std::vector<double> save_state() const;
    /** Restores what save_state wrote, after setup() on the same mesh;
     *  throws std::runtime_error on a size mismatch. */
    void load_state(const std::vector<double> &state);

  private:
    const dealii::parallel::distributed::Triangulation<dim> &triangulation;
    ExplicitSettings                                         settings;
    MPI_Comm                                                 comm;
    dealii::FESystem<dim>                                    fe;
    dealii::MappingQ<dim>                                    mapping;
    dealii::DoFHandler<dim>                                  dof_handler;
    dealii::IndexSet                                         owned;

    dealii::TrilinosWrappers::SparseMatrix stiffness;
    dealii::TrilinosWrappers::MPI::Vector  mass, u, v, f_ext, work;
    dealii::TrilinosWrappers::MPI::Vector  f_boundary; // at factor 1
    double                                 boundary_factor = 0;
    dealii::Tensor<1, dim>                 boundary_sum;
    dealii::Tensor<2, dim>                 affine_rate;
    bool                                   has_affine = false;
    bool                                   kinematic  = false;
    std::vector<dealii::Point<dim>>        dof_point;             // owned dofs, in order
    std::vector<unsigned char>             dof_component;         // same order
    double affine_velocity(std::size_t k) const;                  // of the k-th owned dof
    std::vector<dealii::types::global_dof_index> fixed_dofs;      // owned only
    std::vector<double>                          fixed_velocity;  // same order
    std::vector<unsigned int>                    fixed_component; // same order

    std::vector<dealii::Point<dim>>                               iface_points;
    std::vector<std::array<dealii::types::global_dof_index, dim>> iface_dofs;
    double                                                        current_time = 0;
  };
} // namespace demfem::fem

#endif
