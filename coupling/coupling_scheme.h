#pragma once
// How the continuum answers the grains over one coupling window
// (docs/architecture.md, "Coupling"; coupled_model.h for the two schemes'
// equations). Chosen once, when the coupled model is built
// (Coupling/scheme), so that nothing per step branches on it:
//   ExplicitScheme     the continuum's central-difference dynamics, stepped
//                      by the window k dt under the window's mean forces;
//   QuasiStaticScheme  the continuum's static response u* = lambda u_far + F f
//                      (flexibility F computed once), relaxed by omega;
//   CondensedScheme    the continuum's static stiffness K_s = F^-1 condensed
//                      onto the coupling nodes, which are stepped with the
//                      DEM under local damping to u = lambda u_far + F f.
// A scheme advances the continuum by one window and returns the interface
// motion (displacement at the window start, velocity over the window) the
// DEM side follows; it owns the scheme's state and its checkpoint entries.
#include <deal.II/distributed/tria.h>
#include <deal.II/lac/full_matrix.h>

#include "common/growth_monitor.h"
#include "dem/engine/types.h"
#include "dem/io/state_archive.h"
#include "fem/explicit_dynamics.h"
#include "fem/static_interface.h"

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace demfem::coupling
{
  struct CouplingParams;

  template <int dim>
  class CouplingScheme
  {
  public:
    /// One window of k = subcycles DEM steps.
    struct Window
    {
      /// Mean coupling-node forces of the window (coupling order).
      const std::vector<dealii::Tensor<1, dim>> &forces;
      double       load_factor;    ///< lambda at the window's end
      double       load_increment; ///< lambda's increase over the window
      double       release;        ///< a section's tunnel-wall traction left
      double       length;         ///< k dt [s]
      std::int64_t step;           ///< DEM steps so far (diagnoses)
      /// The continuum stays on the affine path lambda eps0 x (kinematic,
      /// at rest once lambda stops) while the in-situ servo moves the
      /// DEM side (coupled_model.h); only where follows_affine_path().
      bool hold = false;
    };

    virtual ~CouplingScheme()        = default;
    virtual std::string name() const = 0;
    /// Largest DEM step the scheme allows, given the fraction of the
    /// continuum's coupled critical step a window may use.
    virtual double dem_step_limit(double window_fraction) const = 0;
    /// The in-situ strain eps0 (plane strain in plane; 3D e_zz = 0).
    virtual void set_insitu_strain(const dealii::Tensor<2, dim> &eps0) = 0;
    /// Whether free grains are held on the affine installation path while
    /// lambda rises (coupled_model.h): only a continuum that follows the
    /// path exactly can carry them.
    virtual bool follows_affine_path() const = 0;
    /// Advances the continuum by one window; u, v: the coupling nodes'
    /// displacement at the window's start and their velocity over it.
    virtual void advance(const Window &w, std::vector<dem::Vec<dim>> &u,
                         std::vector<dem::Vec<dim>> &v) = 0;
    /// The continuum's kinetic energy (0 without inertia).
    virtual double kinetic_energy() const = 0;
    /// The continuum's unbalanced-force ratio |f - K u| / |K u| (0 for a
    /// continuum solved statically every window).
    virtual double unbalanced_ratio() const = 0;
    /// Relative interface residual |u* - u| / |u*| (0 for the explicit one).
    virtual double residual() const = 0;
    /// What to add to a DEM instability's diagnosis ("" : nothing).
    virtual std::string instability_hint() const = 0;
    /// Coupling-node displacements (coupling order).
    virtual std::vector<dem::Vec<dim>> coupling_displacements() const = 0;
    /// The continuum's displacement field on dof_handler().
    virtual dealii::Vector<double> displacement_field(double load_factor) const = 0;
    virtual const dealii::DoFHandler<dim> &dof_handler() const                  = 0;
    /// Checkpoint entries (dem/io/state_archive.h), one function for both.
    virtual void serialize(dem::StateArchive &ar) = 0;
  };

  /// The scheme of `coupling.scheme` on the continuum `fem` (set up, with
  /// its coupling vertices `points`; `continuum_critical` its critical step
  /// with the grains attached). `affine_installation`: the whole
  /// continuum follows the affine in-situ path (else only its far field,
  /// the wall-facet variant). Progress lines to `progress` when given.
  template <int dim>
  std::unique_ptr<CouplingScheme<dim>> make_coupling_scheme(
      const CouplingParams &coupling, fem::ExplicitDynamics<dim> &fem,
      const dealii::parallel::distributed::Triangulation<dim> &tria,
      const fem::ExplicitSettings                             &settings,
      const std::vector<dealii::Point<dim>> &points, double continuum_critical,
      bool affine_installation, double local_damping, std::ostream *progress);
} // namespace demfem::coupling
