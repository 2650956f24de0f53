// Meshes for the elastic continuum: a generated graded tunnel mesh (no files
// needed) and Gmsh meshes read from disk, with the boundary-id conventions of
// docs/architecture.md, "The continuum":
//   1 far field, 2 interface to a DEM region, 3 tunnel wall,
//   4 faces normal to the tunnel axis (z) carrying a roller (u_z = 0).
#ifndef DEMFEM_FEM_MESH_H
#define DEMFEM_FEM_MESH_H

#include <deal.II/grid/tria.h>

#include <set>
#include <string>

namespace demfem::fem
{
  namespace boundary_id
  {
    constexpr dealii::types::boundary_id far_field   = 1;
    constexpr dealii::types::boundary_id interface   = 2;
    constexpr dealii::types::boundary_id tunnel_wall = 3;
    constexpr dealii::types::boundary_id roller_z    = 4;
  } // namespace boundary_id

  struct GeneratedMeshSettings
  {
    double       radius       = 1.0;  // tunnel radius a
    double       outer_radius = 30.0; // far boundary R
    unsigned int cells_around = 32;   // cells along the tunnel wall
    // 3D only: slab thickness and number of element layers along z.
    double       thickness = 1.0;
    unsigned int layers    = 1;
    // 3D only: if true the z = const faces get id 4 (roller, plane strain
    // slab); otherwise they are far-field faces (id 1).
    bool plane_strain_slab = true;
  };

  /**
   * Fill @p tria with an annulus a <= r <= R around the z axis, graded
   * geometrically in r so that cells stay roughly square (fine at the wall,
   * coarse at the far boundary). In 3D the annulus is extruded along z over
   * [0, thickness]. A polar/cylindrical manifold (id 0) is attached so that
   * refinement and higher-order mappings follow the circles exactly.
   */
  template <int dim>
  void generate_tunnel_mesh(dealii::Triangulation<dim>  &tria,
                            const GeneratedMeshSettings &settings);

  /// A tunnel section embedded in a 3D continuum (docs/architecture.md,
  /// "In-situ stress and excavation"): the DEM section occupies r < b,
  /// 0 <= z <= t; the continuum is the cylinder
  /// r <= R, -L <= z <= t + L with the tunnel r < a through its whole length
  /// and, inside the section, the hole r < r_in, h <= z <= t - h (the part of
  /// the section the continuum does not overlap: r_in = b - h and the end
  /// layers 0 <= z <= h, t - h <= z <= t, a < r, overlap the DEM's rim and
  /// ends).
  struct SectionMeshSettings
  {
    double       tunnel_radius  = 0.4; ///< a
    double       hole_radius    = 0.8; ///< r_in (> a)
    double       section_length = 1.0; ///< t
    double       end_overlap    = 0.2; ///< h (t > 2 h)
    double       extension      = 2.0; ///< L (> 0)
    double       outer_radius   = 10;  ///< R (> r_in)
    unsigned int cells_around   = 32;
    /// Target element size along z in the section and radially between a
    /// and r_in [m].
    double element_size = 0.2;
  };

  /**
   * Fill @p tria with the continuum of SectionMeshSettings: hexahedra on
   * rings (radial a .. r_in uniform, r_in .. R geometric as
   * generate_tunnel_mesh) and layers (one through each end overlap, uniform
   * in the section, geometric outwards to the ends). Boundary ids: 1 the
   * cylinder r = R, 4 the end planes z = -L, t + L (rollers), 3 the tunnel
   * wall r = a outside the section (z < 0 or z > t), 2 every other inner
   * face (the faces that bound the DEM section). Cylindrical manifold 0.
   */
  void generate_section_mesh(dealii::Triangulation<3>  &tria,
                             const SectionMeshSettings &settings);

  /**
   * Read a Gmsh .msh file (ASCII, format 2 or 4, quadrilaterals/hexahedra).
   * Physical tags of boundary entities become boundary ids. Circular
   * boundaries with id 2 and 3 (centred on the z axis) get a cylindrical
   * manifold so refinement stays on the circle; planar parts (e.g. a tunnel
   * face) stay flat.
   */
  template <int dim>
  void read_gmsh_mesh(dealii::Triangulation<dim> &tria, const std::string &file);

  /**
   * Boundary ids present on the coarse mesh (valid for distributed
   * triangulations since level 0 is replicated on every rank).
   */
  template <int dim>
  std::set<dealii::types::boundary_id> coarse_boundary_ids(
      const dealii::Triangulation<dim> &tria);

} // namespace demfem::fem

#endif
