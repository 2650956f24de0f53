#pragma once
// Wall-facet coupling of the embedded DEM region and the explicit-dynamic
// continuum (DESIGN §5, as PFC-FLAC wall-zone coupling), 2D.
//
// The continuum (fem::ExplicitDynamics, Q1, far field fixed) covers
// b <= r <= R; its interface circle r = b (boundary id 2) is a closed ring of
// DEM wall facets whose vertices are the continuum's interface vertices. The
// facets move with the nodal velocities; the contact force the grains exert
// on each facet is split onto its two vertices by the barycentric weights of
// the contact point (dem::Walls::vertex_force) and applied to the continuum
// as nodal forces, so the force sum is exactly preserved (checked every
// continuum step, imbalance recorded).
//
// Staggered explicit-explicit scheme with k = subcycles: every k DEM steps
// the continuum advances by k dt under the mean vertex force of the previous
// k DEM steps; the ring vertices then move with the new nodal velocities
// v_{n+k/2} for the next k DEM steps, which is exactly the linear
// interpolation of the nodal motion u_n -> u_{n+k} (positions stay
// consistent; the wall work the DEM books is the work the continuum
// receives). Common time step dt = safety min(DEM critical, continuum
// critical / k).
//
// In-situ stress. The continuum starts unstressed; its far-field boundary
// (fixed, r = R) is moved to u = lambda eps0 x, eps0 the plane-strain strain
// of sigma0 in the continuum, with the load factor lambda ramped from 0 to 1.
// A region whose constants match the continuum's then carries sigma0 exactly
// (homogeneous field); the fixed far field differs from a traction far field
// by O((a/R)^2) for the excavation.
#include <deal.II/distributed/tria.h>

#include "coupling/dem_region.h"
#include "fem/explicit_dynamics.h"

#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace demfem::coupling
{
  struct ContinuumParams
  {
    double       young_modulus = 60e9; ///< plane-strain E [Pa]
    double       poisson_ratio = 0.25;
    double       density       = 2650;
    double       outer_radius  = 30; ///< R [m]
    unsigned int cells_around  = 0;  ///< 0: facets about 2 mean grain diameters long
    double       damping       = -1; ///< mass-proportional a [1/s]; < 0: automatic
    double       mass_scaling  = 1;
  };

  struct CouplingParams
  {
    /// "slaved-layer" or "wall-facets" (DESIGN §5).
    std::string  variant    = "wall-facets";
    /// "explicit" (continuum stepped every `subcycles` DEM steps) or
    /// "quasi-static" (static continuum response, relaxed).
    std::string  scheme     = "explicit";
    unsigned int subcycles  = 1;
    double       safety     = 0.8;
    double       relaxation = 1.0; ///< quasi-static relaxation factor, (0, 2)
  };

  /// Doubles as hex text of their bytes (checkpoint metadata strings):
  /// bit-exact, so a restarted run continues bit for bit (DESIGN §8).
  std::string         encode_doubles(const std::vector<double> &v);
  std::vector<double> decode_doubles(const std::string &s, const std::string &what);

  class WallFacetModel
  {
  public:
    WallFacetModel(const RegionParams &region, const ContinuumParams &continuum,
                   const CouplingParams &coupling, MPI_Comm comm);
    ~WallFacetModel();

    /// Mesh, continuum, ring walls, packing and bonding; time step.
    void build(std::ostream *progress = nullptr);

    /// In-situ stress (tension positive) and its load factor (ramp).
    void   set_insitu(const Eigen::Matrix2d &sigma0);
    void   set_load_factor(double f) { load_factor = f; }
    double get_load_factor() const { return load_factor; }

    /// One DEM step (and a continuum step every `subcycles` DEM steps).
    /// Throws dem::InstabilityError with a diagnosis on divergence.
    void step();

    double dt() const { return dt_; }
    double dem_critical() const { return dem_crit; }
    double fem_critical() const { return fem_crit; }
    /// Largest relative interface force imbalance |sum DEM - sum FEM| /
    /// sum |vertex force| seen so far, and the latest one.
    double imbalance_max() const { return imb_max; }
    double imbalance_last() const { return imb_last; }
    double continuum_kinetic_energy() const;

    /// Checkpoint state besides dem's own (dem::write_checkpoint): the
    /// continuum vectors and the coupling's accumulators and counters, as
    /// metadata strings ("coupling.*"). Serial runs only. load_state expects
    /// a model built from the same parameters (after build and set_insitu).
    std::map<std::string, std::string> save_state() const;
    void        load_state(const std::map<std::string, std::string> &meta);
    std::size_t n_fem_dofs() const;

    dem::Model<2>                   dem;
    RegionGroups                    groups;
    fem::ExplicitDynamics<2>       &continuum() { return *fem_; }
    const fem::ExplicitDynamics<2> &continuum() const { return *fem_; }
    const dealii::parallel::distributed::Triangulation<2> &triangulation() const
    {
      return tria;
    }
    const RegionParams &region_params() const { return rp; }
    int                 ring_wall() const { return wall_id; }

  private:
    RegionParams                                    rp;
    ContinuumParams                                 cp;
    CouplingParams                                  kp;
    dealii::parallel::distributed::Triangulation<2> tria;
    std::unique_ptr<fem::ExplicitDynamics<2>>       fem_;
    int                                             wall_id = -1;
    std::vector<int>         ring_vertex;  // FEM interface index -> wall vertex
    std::vector<dem::Vec<2>> X0;           // reference positions (FEM order)
    std::vector<dem::Vec<2>> preload_unit; // -int N sigma0 n ds per vertex
    std::vector<dem::Vec<2>> accum;        // summed vertex forces (FEM order)
    dem::Vec<2>              accum_contacts = dem::Vec<2>::Zero();
    double                   accum_abs      = 0;
    unsigned int             n_accum        = 0;
    double                   load_factor = 0, dt_ = 0, dem_crit = 0, fem_crit = 0;
    double                   imb_max = 0, imb_last = 0;
    double                   last_fem_ke = 0;
    int                      fem_growth  = 0;
    std::int64_t             n_steps     = 0;
    Eigen::Matrix2d sigma0 = Eigen::Matrix2d::Zero(), eps0 = Eigen::Matrix2d::Zero();
    double          applied_factor = 0;
    bool            far_moving     = false;
    void            fem_step();
  };
} // namespace demfem::coupling
