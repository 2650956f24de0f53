#pragma once
// Wall-facet coupling of the embedded DEM region and the explicit-dynamic
// continuum (docs/architecture.md, "Wall facets"; as PFC-FLAC wall-zone
// coupling), 2D and 3D.
//
// The continuum covers b <= r <= R; its interface circle r = b (boundary id
// 2) is a closed ring of DEM wall facets whose vertices are the continuum's
// interface vertices (the coupling nodes). The facets move with the nodal
// velocities; the contact force the grains exert on each facet is split onto
// its vertices by the barycentric weights of the contact point
// (dem::Walls::vertex_force) and applied to the continuum as nodal forces,
// so the force sum is exactly preserved. Time scheme, force-balance check,
// in-situ ramp and checkpoints: coupled_model.h. 3D (slab): the hole's
// quad faces (straight chords x z layers, planar) are split into two
// triangles each, so the facet surface is exactly the continuum's.
#include "coupling/coupled_model.h"

namespace demfem::coupling
{
  template <int dim>
  class WallFacetModel : public CoupledModel<dim>
  {
  public:
    using CoupledModel<dim>::CoupledModel;
    using CoupledModel<dim>::dem;
    using CoupledModel<dim>::groups;
    using CoupledModel<dim>::rp;

    std::string variant() const override { return "wall-facets"; }
    int         ring_wall() const { return wall_id; }

  protected:
    double                          inner_radius() const override { return rp.radius; }
    std::vector<dealii::Point<dim>> build_interface(std::ostream *progress) override;
    dem::Vec<dim> gather_forces(std::vector<dem::Vec<dim>> &nodal) const override;
    /// The former in-situ path (CoupledModel::affine_installation): the
    /// rigid ring next to grains held on the affine path oscillated against
    /// them (measured: subcycles >= 5 diverged within two windows), and with
    /// the continuum affine and the grains free the continuum's growth check
    /// fired at a/d = 3-4 with subcycles 1.
    bool affine_installation() const override { return false; }
    void move_interface(const std::vector<dem::Vec<dim>> &u,
                        const std::vector<dem::Vec<dim>> &v) override;

  private:
    int                        wall_id = -1;
    std::vector<int>           ring_vertex; // coupling index -> wall vertex
    std::vector<dem::Vec<dim>> X0;          // reference positions (coupling order)
  };
} // namespace demfem::coupling
