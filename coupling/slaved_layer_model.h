#pragma once
// Slaved-layer coupling of the embedded DEM region and the continuum
// (docs/architecture.md, "Slaved layer"; the default variant), 2D and 3D
// (slab, dem_region.h).
//
// The region (disk of radius b) is packed and bonded inside a temporary
// ring of wall facets at r = b; the ring then takes no part in the coupling
// (its contacts get a null law, no new ones are made). The continuum covers
// b - h <= r <= R, overlapping the region's outer rim by h (Coupling/overlap
// grains mean grain diameters). Grains whose centres lie in the overlap
// (r > b - h) are slaved (dem fixity fix_all, Particles::group = slaved_tag):
//   v_p = sum_a N_a(X_p) v_a,   w_p = 0.5 curl v (X_p) = 0.5 sum_a grad N_a x v_a
// X_p the reference position (cell and unit point located once), and the
// positions are re-synchronized x_p = X_p + sum_a N_a u_a at every continuum
// step. The force f and moment m that free grains exert on a slaved grain go
// to the nodes of its cell as
//   f_a += N_a f + 0.5 m x grad N_a   (2D: m 0.5 (-dN_a/dy, dN_a/dx)),
// the work conjugate of the slaved velocity and rotation (the power f.v_p +
// m w_p equals sum_a f_a.v_a: energy-consistent); the nodal forces sum to
// sum f exactly (partition of unity, sum_a grad N_a = 0). Contacts between two
// slaved grains (bonds included, and new ones through the model's
// new-contact rule) get a null law (zero stiffness): the overlap's stiffness
// is the continuum's only, not twice. Bonds between free and slaved grains
// stay and carry tension and shear. 3D: the slaved grains' contacts with the
// slab walls get the null law too (the continuum's rollers hold the overlap
// in z).
#include "coupling/coupled_model.h"

#include <array>

namespace demfem::coupling
{
  template <int dim>
  class SlavedLayerModel : public CoupledModel<dim>
  {
  public:
    using CoupledModel<dim>::CoupledModel;
    using CoupledModel<dim>::dem;
    using CoupledModel<dim>::groups;
    using CoupledModel<dim>::rp;
    using CoupledModel<dim>::kp;
    static constexpr unsigned int n_nodes = 1u << dim; ///< nodes of a cell (Q1)

    /// Particles::group tag of the slaved grains.
    static constexpr int slaved_tag = 2;

    std::string variant() const override { return "slaved-layer"; }
    /// Overlap width h [m].
    double overlap() const { return kp.overlap_grains * rp.mean_diameter(); }
    /// Number of slaved grains.
    std::size_t n_slaved() const { return slaved.size(); }
    /// Law group of the slaved-slaved contacts (null law).
    int null_group() const { return null_ball; }

  protected:
    double inner_radius() const override { return rp.radius - overlap(); }
    std::vector<dealii::Point<dim>> build_interface(std::ostream *progress) override;
    dem::Vec<dim> gather_forces(std::vector<dem::Vec<dim>> &nodal) const override;
    void          move_interface(const std::vector<dem::Vec<dim>> &u,
                                 const std::vector<dem::Vec<dim>> &v) override;
    void          add_attached_stiffness(std::vector<double> &k) const override;
    /// Measured (docs/tunnel.md): with the grains bonded to the slaved
    /// layer, the lagged window is stable up to about half the coupled
    /// limit (a/d = 4, grains as stiff as the continuum: k dt = 1.4e-5 s
    /// stable, 2.0e-5 s stalls, 2.4e-5 s wrong; coupled limit 3.0e-5 s).
    double window_limit_fraction() const override { return 0.5; }

  private:
    /// A slaved grain: its stable id, reference position and the nodes of
    /// its cell (coupling index), with N_a(X) and grad N_a(X).
    struct Slave
    {
      std::int64_t                       id = 0;
      dem::Vec<dim>                      X  = dem::Vec<dim>::Zero();
      std::array<unsigned int, n_nodes>  node{};
      std::array<double, n_nodes>        N{};
      std::array<dem::Vec<dim>, n_nodes> dN{};
    };
    std::vector<Slave> slaved;
    int                null_ball = -1, null_wall = -1;
    /// Particle index of each slave (refreshed when particles are removed).
    mutable std::vector<std::int64_t> index;
    mutable std::size_t               index_n = 0;
    void                              refresh_index() const;
  };
} // namespace demfem::coupling
