#pragma once
// The coupled model of the embedded DEM region and the continuum
// (docs/architecture.md, "Coupling"), 2D and 3D (template on dim, instantiated
// for 2 and 3): what the two kinematic variants share. The tunnel workflow
// (tunnel_run.cc) works on this interface only.
//
// The continuum (fem::ExplicitDynamics, Q1, far field fixed) is an annulus
// r_in <= r <= R; a variant decides r_in, builds the DEM side and names the
// coupling nodes (continuum vertices): the ring vertices of the wall-facet
// variant (wall_facet_model.h) or the nodes of the cells overlapped by the
// slaved layer (slaved_layer_model.h). After every DEM step the variant adds
// the force the grains exert on each coupling node (consistent nodal forces,
// summing exactly to the DEM forces on the interface); after every continuum
// step it moves its interface with the nodal displacements and velocities.
//
// Staggered explicit-explicit scheme with k = subcycles: every k DEM steps
// the continuum advances by k dt under the mean coupling-node force of the
// previous k DEM steps; the interface then moves with the new nodal
// velocities v_{n+k/2} for the next k DEM steps, which is exactly the linear
// interpolation of the nodal motion u_n -> u_{n+k} (positions are
// re-synchronized at every continuum step; the work the DEM books at the
// interface is the work the continuum receives). Common time step
// dt = safety min(DEM critical, continuum critical / k).
//
// Force balance, every continuum step: the nodal forces the continuum holds
// sum to the mean of the DEM-side interface force (contact sums computed
// independently of the nodal distribution); the relative difference is
// recorded as interface_force_imbalance.
//
// In-situ stress, installed kinematically (docs/tunnel.md, "In-situ stress
// installation"). Everything starts unstressed; while the load factor lambda
// rises from 0 to 1 the whole model follows the homogeneous in-situ strain
// field u = lambda eps0 x (eps0 the plane-strain strain of sigma0 in the
// continuum): every continuum node moves with the affine velocity
// (d lambda/dt) eps0 x, its dynamic part held at zero
// (ExplicitDynamics::set_kinematic; the far field is fixed at
// u = lambda eps0 x), and every free grain's translation is held on the
// same affine path (its rotation stays free). No wave is launched and
// nothing carries an inertial load, so the state at lambda = 1 does not
// depend on the ramp's length, the time step or the sub-cycling. At
// lambda = 1 the grains and the continuum are released at rest and the model relaxes the
// non-affine part (the grains' own rearrangement) to equilibrium. A region
// whose constants match the continuum's then carries sigma0 (homogeneous
// field); the fixed far field differs from a traction far field by
// O((a/R)^2) for the excavation. The quasi-static scheme has no continuum
// dynamics to shock: its interface relaxes towards lambda u_far + F f and
// the grains stay free (holding them on the affine path while the relaxed
// interface lags behind made the slaved layer unstable, measured).

//
// Quasi-static scheme (Coupling/scheme = quasi-static). The continuum has
// no inertia: its response at the coupling nodes is
//   u* = lambda u_far + F f
// (fem::StaticInterfaceResponse: F the interface flexibility, factorized
// and computed once; u_far the response to the far-field strain eps0). Every
// k = subcycles DEM steps, f is the mean coupling-node force of the window,
// the target relaxed, u_new = u + omega (u* - u) (omega = Coupling/relaxation,
// a Dirichlet-Neumann iteration: for an interface whose DEM side is about as
// stiff as the continuum the error factor is 1 - 2 omega, optimum 0.5;
// grain-scale interface modes are stiffer, measured: omega = 1 diverges,
// 0.5 is marginal, 0.3 converges, with subcycles = 200 DEM steps so that
// the DEM responds within a window; subcycles <= 50 diverged), and
// the coupling nodes move linearly to u_new over the next window. The
// relative interface residual |u* - u| / |u*| is recorded; it growing by
// more than 20 % per window for 15 windows (or a non-finite value) stops the
// run with a diagnosis naming relaxation, subcycles and stiffness contrast.
// dt = safety x DEM critical step (no continuum limit).
//
// Condensed scheme (Coupling/scheme = condensed; coupling_scheme.h). The
// continuum has no inertia and is condensed onto the coupling nodes by its
// static interface stiffness K_s = F^-1; the nodes are stepped with the DEM,
//   M a = f - K_s (u - lambda u_far)  with local non-viscous damping,
// M the continuum's lumped nodal masses. At rest u = lambda u_far + F f. The
// nodes follow lambda eps0 x while lambda rises (as the grains) and are
// released at rest. dt as the explicit scheme's (K_s is a Schur complement
// of the continuum's stiffness: its frequencies are bounded by the coupled
// continuum's).
#include <deal.II/distributed/tria.h>

#include "common/growth_monitor.h"
#include "coupling/coupling_scheme.h"
#include "coupling/dem_region.h"
#include "dem/io/state_archive.h"
#include "fem/explicit_dynamics.h"
#include "fem/static_interface.h"

#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace demfem::coupling
{
  struct CouplingParams; // below: the coupling keys ContinuumParams::validate reads

  struct ContinuumParams
  {
    double       young_modulus = 60e9; ///< plane-strain E [Pa]
    double       poisson_ratio = 0.25;
    double       density       = 2650;
    double       outer_radius  = 30; ///< R [m]
    unsigned int cells_around  = 0;  ///< 0: cells about 2 mean grain diameters wide
    double       damping       = -1; ///< mass-proportional a [1/s]; < 0: automatic
    /// Density scaling of the continuum (its static response does not
    /// depend on it). <= 0: automatic (explicit scheme): the lightest
    /// continuum whose coupled critical step still admits the DEM's, so
    /// that its waves cross and its damping acts in as few DEM steps as
    /// possible, never heavier than the physical one (docs/tunnel.md,
    /// "Where the steps go").
    double mass_scaling = 1;
    /// 3D: length L of continuum beyond each end of the DEM section [m].
    /// 0: the plane-strain slab (continuum over 0 <= z <= t only); > 0: a
    /// tunnel section in a 3D continuum (below; slaved layer, explicit).
    double axial_extension = 0;
    /// Tunnel radius a (the tunnel through the continuum of a section) [m].
    double tunnel_radius = 0;

    /// Throws dem::InputError naming the key (prefixed by `where`): E > 0,
    /// -1 < nu < 0.5, R > 2 b (b = region_radius), L >= 0; L > 0 only in 3D
    /// with the slaved layer and the explicit scheme (`coupling`, validated
    /// before) and a tunnel radius > 0. The one check of these keys, for
    /// the tunnel parameters and the coupled model alike.
    void validate(const std::string &where, int dim, double region_radius,
                  const CouplingParams &coupling) const;
  };

  struct CouplingParams
  {
    /// "slaved-layer" or "wall-facets" (docs/architecture.md, "Coupling").
    std::string variant = "slaved-layer";
    /// "explicit" (continuum stepped every `subcycles` DEM steps) or
    /// "quasi-static" (static continuum response, relaxed).
    std::string  scheme    = "explicit";
    unsigned int subcycles = 1;
    double       safety    = 0.8;
    /// Quasi-static relaxation factor omega, (0, 2); with subcycles = 200
    /// 0.5 converged on a/d = 12 regions and diverged on a/d = 18, 0.3 on both.
    double relaxation = 0.3;
    /// Slaved layer: width h of the overlap of the continuum and the DEM
    /// region, in mean grain diameters (Coupling/overlap grains).
    double overlap_grains = 2.0;

    /// Throws dem::InputError naming the key (prefixed by `where`).
    void validate(const std::string &where) const;
  };

  /// Doubles as hex text of their bytes (checkpoint metadata strings):
  /// bit-exact, so a restarted run continues bit for bit
  /// (docs/architecture.md, "Checkpoints and restart").

  /// 3D slab of the 2D problem (plane strain through walls):
  /// the continuum is the annulus extruded over 0 <= z <= t (t =
  /// RegionParams::slab_thickness, element layers about two mean grain
  /// diameters thick) with rollers (u_z = 0) on its z faces; the DEM region
  /// is the slab of spheres between two fixed frictionless walls z = 0, t
  /// (dem_region.h). The in-situ stress is given in plane; szz = nu (sxx +
  /// syy) follows from plane strain on both sides (the continuum's far-field
  /// strain has e_zz = 0, the grains push on the slab walls).
  ///
  /// 3D tunnel section in a 3D continuum (ContinuumParams::axial_extension
  /// L > 0): the DEM section (r < b, 0 <= z <= t, spheres packed
  /// and bonded as the slab) is surrounded by continuum on every side: the
  /// mesh (fem::generate_section_mesh) covers r <= R, -L <= z <= t + L
  /// with the tunnel r < a through its whole length, and overlaps the
  /// section's rim (r > b - h) and both ends (z < h, z > t - h, r > a) by
  /// the slaved layer's width h; grains whose centres lie in the continuum
  /// are slaved (in_continuum). The ends z = -L, t + L are on rollers (as
  /// the rock far ahead and behind a long tunnel), the far cylinder moves
  /// with the in-situ strain, and the continuum's tunnel wall (r = a outside
  /// the section) carries the traction sigma0.n of the rock it replaces,
  /// ramped with the load factor and released by excavation
  /// (set_excavation_release). The free core r < a of the section keeps the
  /// fixed frictionless walls z = 0, t until it is excavated. With the
  /// tunnel excavated along the whole length the exact answer is plane
  /// strain, so Kirsch checks the section's ends too.
  template <int dim>
  class CoupledModel
  {
  public:
    CoupledModel(const RegionParams &region, const ContinuumParams &continuum,
                 const CouplingParams &coupling, MPI_Comm comm);
    virtual ~CoupledModel();

    /// "slaved-layer" or "wall-facets".
    virtual std::string variant() const = 0;
    /// "explicit" or "quasi-static".
    const std::string &scheme() const { return kp.scheme; }

    /// Mesh, continuum, DEM region (packing and bonding), interface; time
    /// step.
    void build(std::ostream *progress = nullptr);

    /// In-situ stress (tension positive) and its load factor (ramp).
    /// In plane (xx, xy, yy); 3D: szz from plane strain.
    void set_insitu(const Eigen::Matrix2d &sigma0);
    void set_load_factor(double f) { load_factor = f; }
    /// Tunnel section (3D): remaining fraction of the in-situ traction on
    /// the continuum's tunnel wall (1 before excavation, 0 when excavated).
    void   set_excavation_release(double remaining) { release = remaining; }
    double get_excavation_release() const { return release; }
    /// A tunnel section in a 3D continuum (ContinuumParams::axial_extension).
    bool section() const { return dim == 3 && cp.axial_extension > 0; }
    /// Whether a point lies in the continuum (the slaved layer's overlap
    /// incl. a section's end layers).
    bool in_continuum(const dem::Vec<dim> &x) const;
    /// Width of the continuum's overlap of the section's ends (and rim) [m].
    double end_overlap() const { return rp.radius - inner_radius(); }
    double get_load_factor() const { return load_factor; }
    /// Whether grains are still held on the in-situ installation's path
    /// (released at the first continuum step after lambda stopped
    /// changing): no equilibrium can be declared before.
    bool installing() const { return !installing_grains.empty(); }

    /// In-situ stress servo (docs/tunnel.md, "In-situ stress servo";
    /// coupling/in_situ_servo.h). While held, the continuum stays on the
    /// affine in-situ path (lambda eps0 x, kinematic; at rest once lambda
    /// stops), so that the DEM side alone answers the interface strain.
    void hold_continuum(bool on) { hold = on; }
    bool continuum_held() const { return hold; }
    /// Whether the interface follows the affine in-situ path (the slaved
    /// layer with the explicit scheme, or the condensed scheme): the servo
    /// needs it.
    bool follows_affine_path() const;
    /// Interface strain E (in plane; 3D: E_zz = E_xz = E_yz = 0): the DEM
    /// side of the interface sits at u + E X instead of u (u the
    /// continuum's coupling-node displacement, X the reference position),
    /// an eigenstrain of the region relative to the continuum. A change is
    /// applied over the next continuum window with the free grains held on
    /// its affine path (as the load factor), so nothing is shocked; the
    /// continuum's own displacement and stress do not change.
    void            set_interface_strain(const Eigen::Matrix2d &E);
    Eigen::Matrix2d interface_strain() const;
    /// The in-situ stress (in plane) and the continuum's in-situ strain.
    const Eigen::Matrix2d &insitu_stress() const { return sigma0; }
    Eigen::Matrix2d        insitu_strain_in_plane() const
    {
      return eps0.template topLeftCorner<2, 2>();
    }

    /// One DEM step (and a continuum update every `subcycles` DEM steps).
    /// Throws dem::InstabilityError with a diagnosis on divergence.
    void step();

    double dt() const { return dt_; }
    double dem_critical() const { return dem_crit; }
    double fem_critical() const { return fem_crit; }
    /// Largest relative interface force imbalance |sum DEM - sum FEM| /
    /// sum |nodal force| seen so far, and the latest one.
    double imbalance_max() const { return imb_max; }
    double imbalance_last() const { return imb_last; }
    /// Kinetic energy of the continuum (0 for the quasi-static scheme).
    double continuum_kinetic_energy() const;
    /// The continuum's unbalanced-force ratio (fem::ExplicitDynamics::
    /// unbalanced_force_ratio; 0 for the quasi-static scheme).
    double continuum_unbalanced_ratio() const;
    /// Quasi-static scheme: relative interface residual |u* - u| / |u*| of
    /// the latest window; condensed: |f - K_s (u - lambda u_far)| /
    /// |K_s (u - lambda u_far)| (0 for the explicit scheme).
    double interface_residual() const;
    /// Force the grains exert on the continuum at the latest DEM step (sum
    /// over the interface) [N].
    dem::Vec<dim> interface_force() const { return last_force; }

    /// Checkpoint state besides dem's own (dem::write_checkpoint): the
    /// continuum vectors and the coupling's accumulators and counters, as
    /// named entries "coupling.*" / "continuum.*" (dem/io/state_archive.h),
    /// one function for saving and loading. Serial runs only. Loading
    /// expects a model built from the same parameters (after build and
    /// set_insitu) and checks the sizes.
    void serialize(dem::StateArchive &ar);
    /// Wall time spent in the parts of step() since construction [s]: the
    /// continuum step (with the interface motion it imposes), the DEM step,
    /// gathering the interface forces (where the steps go, docs/study.md).
    struct StepTimes
    {
      double continuum = 0, dem = 0, interface = 0;
    };
    const StepTimes &step_times() const { return times; }

    /// "variant scheme": stored with a checkpoint, compared on restart.
    std::string checkpoint_tag() const { return variant() + " " + scheme(); }
    std::size_t n_fem_dofs() const;

    /// Coupling nodes (continuum vertices) and their displacements, same
    /// order.
    const std::vector<dealii::Point<dim>> &coupling_points() const;
    std::vector<dem::Vec<dim>>             coupling_displacements() const;

    /// The continuum's displacement field for output (explicit: the
    /// dynamic state; quasi-static: a static solve with the current
    /// interface forces) on dof_handler().
    dealii::Vector<double> displacement_field() const;
    /// The continuum as VTK XML (.vtu) text: displacement and the total
    /// stress components per cell (stress_xx, ...), for ParaView.
    std::string                    continuum_vtu() const;
    const dealii::DoFHandler<dim> &dof_handler() const;
    double                         continuum_inner_radius() const;

    dem::Model<dim>                   dem;
    RegionGroups                      groups;
    fem::ExplicitDynamics<dim>       &continuum() { return *fem_; }
    const fem::ExplicitDynamics<dim> &continuum() const { return *fem_; }
    const dealii::parallel::distributed::Triangulation<dim> &triangulation() const
    {
      return tria;
    }
    const RegionParams   &region_params() const { return rp; }
    const CouplingParams &coupling_params() const { return kp; }

  protected:
    /// Inner radius of the continuum annulus.
    virtual double inner_radius() const = 0;
    /// Builds the DEM side once the continuum is set up (its boundary-id-2
    /// vertices are those of the inner circle) and returns the coupling
    /// nodes (mesh vertices) in a fixed order.
    virtual std::vector<dealii::Point<dim>> build_interface(std::ostream *progress) = 0;
    /// After a DEM step: adds the force the grains exert on each coupling
    /// node to `nodal` (coupling order), and returns the DEM-side sum of the
    /// same forces (contact sums, independent of the distribution).
    virtual dem::Vec<dim> gather_forces(std::vector<dem::Vec<dim>> &nodal) const = 0;
    /// The coupling nodes are at displacement u and move with velocity v
    /// over the next window (coupling order).
    virtual void move_interface(const std::vector<dem::Vec<dim>> &u,
                                const std::vector<dem::Vec<dim>> &v) = 0;
    /// Adds to k (coupling order) a bound of the DEM contact stiffness
    /// [N/m] the interface hangs on each coupling node: the continuum's
    /// explicit step must also resolve the coupling nodes oscillating on
    /// the grains' contacts (default: none).
    virtual void add_attached_stiffness(std::vector<double> &k) const { (void)k; }
    /// Whether the in-situ stress is installed on the affine path (above;
    /// default). false: the far field alone is moved to u = lambda eps0 x
    /// and the grains stay free (the wall-facet variant, wall_facet_model.h).
    virtual bool affine_installation() const { return true; }
    /// Fraction of the coupled continuum limit a sub-cycled window k dt may
    /// use (the interface forces of a window act on the next one: a lag).
    virtual double window_limit_fraction() const { return 1.0; }

    RegionParams    rp;
    ContinuumParams cp;
    CouplingParams  kp;

  private:
    dealii::parallel::distributed::Triangulation<dim> tria;
    std::unique_ptr<fem::ExplicitDynamics<dim>>       fem_;
    std::vector<dealii::Point<dim>>                   points;
    std::vector<dem::Vec<dim>> accum; // summed nodal forces over the window
    std::vector<dem::Vec<dim>> nodal; // nodal forces of one DEM step
    // One window's mean nodal forces and the interface motion the scheme
    // returns, kept so that a window (every step with subcycles = 1)
    // allocates nothing.
    std::vector<dealii::Tensor<1, dim>> window_forces;
    std::vector<dem::Vec<dim>>          window_u, window_v;
    dem::Vec<dim>                       accum_contacts = dem::Vec<dim>::Zero();
    dem::Vec<dim>                       last_force     = dem::Vec<dim>::Zero();
    double                              accum_abs      = 0;
    unsigned int                        n_accum        = 0;
    double       load_factor = 0, dt_ = 0, dem_crit = 0, fem_crit = 0;
    double       release = 1; // section: tunnel-wall traction left
    double       imb_max = 0, imb_last = 0;
    std::int64_t n_steps = 0;
    /// In-situ stress (in plane) and the continuum's far-field strain (3D:
    /// plane strain, e_zz = e_xz = e_yz = 0).
    Eigen::Matrix2d                 sigma0 = Eigen::Matrix2d::Zero();
    Eigen::Matrix<double, dim, dim> eps0   = Eigen::Matrix<double, dim, dim>::Zero();
    double                          applied_factor = 0;
    /// Kinematic in-situ installation: the affine strain rate of the
    /// current continuum window and the grains held on the affine path
    /// (free grains when it began; their translation fixity is restored
    /// when lambda stops changing).
    Eigen::Matrix<double, dim, dim> install_rate =
        Eigen::Matrix<double, dim, dim>::Zero();
    std::vector<double> installing_grains;
    /// In-situ servo: the continuum held, the interface strain asked and
    /// the one applied so far (coupled_model.h above).
    bool                            hold = false;
    Eigen::Matrix<double, dim, dim> interface_eps =
        Eigen::Matrix<double, dim, dim>::Zero();
    Eigen::Matrix<double, dim, dim> applied_interface_eps =
        Eigen::Matrix<double, dim, dim>::Zero();
    void hold_grains_on_affine_path(double dl, const Eigen::Matrix<double, dim, dim> &dE);
    dealii::Tensor<2, dim> insitu_strain() const;
    void                   continuum_step();
    /// How the continuum answers over a window (coupling_scheme.h), chosen
    /// once in build().
    std::unique_ptr<CouplingScheme<dim>> scheme_;
    StepTimes                            times;
  };

  /// The model of CouplingParams::variant ("slaved-layer" or "wall-facets").
  template <int dim>
  std::unique_ptr<CoupledModel<dim>> make_coupled_model(const RegionParams    &region,
                                                        const ContinuumParams &continuum,
                                                        const CouplingParams  &coupling,
                                                        MPI_Comm               comm);
  /// The 2D model (what the 2D callers use).
  inline std::unique_ptr<CoupledModel<2>> make_coupled_model(
      const RegionParams &region, const ContinuumParams &continuum,
      const CouplingParams &coupling, MPI_Comm comm)
  {
    return make_coupled_model<2>(region, continuum, coupling, comm);
  }
} // namespace demfem::coupling
