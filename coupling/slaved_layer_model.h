#pragma once
// Slaved-layer coupling of the embedded DEM region and the continuum (DESIGN
// §5, the default variant), 2D.
//
// The region (disk of radius b) is packed and bonded inside a temporary
// ring of wall facets at r = b; the ring then takes no part in the coupling
// (its contacts get a null law, no new ones are made). The continuum covers
// b - h <= r <= R, overlapping the region's outer rim by h (Coupling/overlap
// grains mean grain diameters). Grains whose centres lie in the overlap
// (r > b - h) are slaved (dem fixity fix_all, Particles::group = slaved_tag):
//   v_p = sum_a N_a(X_p) v_a,   w_p = 0.5 (dv_y/dx - dv_x/dy)(X_p),
// X_p the reference position (cell and unit point located once), and the
// positions are re-synchronized x_p = X_p + sum_a N_a u_a at every continuum
// step. The force f and moment m that free grains exert on a slaved grain go
// to the nodes of its cell as
//   f_a += N_a f + m 0.5 (-dN_a/dy, dN_a/dx),
// the work conjugate of the slaved velocity and rotation (the power f.v_p +
// m w_p equals sum_a f_a.v_a: energy-consistent); the nodal forces sum to
// sum f exactly (partition of unity, sum_a grad N_a = 0). Contacts between two
// slaved grains (bonds included, and new ones through the model's
// new-contact rule) get a null law (zero stiffness): the overlap's stiffness
// is the continuum's only, not twice. Bonds between free and slaved grains
// stay and carry tension and shear.
#include "coupling/coupled_model.h"

#include <array>

namespace demfem::coupling
{
  class SlavedLayerModel : public CoupledModel
  {
  public:
    using CoupledModel::CoupledModel;

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
    std::vector<dealii::Point<2>> build_interface(std::ostream *progress) override;
    dem::Vec<2> gather_forces(std::vector<dem::Vec<2>> &nodal) const override;
    void        move_interface(const std::vector<dem::Vec<2>> &u,
                               const std::vector<dem::Vec<2>> &v) override;

  private:
    /// A slaved grain: its stable id, reference position and the four nodes
    /// of its cell (coupling index), with N_a(X) and grad N_a(X).
    struct Slave
    {
      std::int64_t                id = 0;
      dem::Vec<2>                 X  = dem::Vec<2>::Zero();
      std::array<unsigned int, 4> node{};
      std::array<double, 4>       N{};
      std::array<dem::Vec<2>, 4>  dN{};
    };
    std::vector<Slave> slaved;
    int                null_ball = -1, null_wall = -1;
    /// Particle index of each slave (refreshed when particles are removed).
    mutable std::vector<std::int64_t> index;
    mutable std::size_t               index_n = 0;
    void                              refresh_index() const;
  };
} // namespace demfem::coupling
