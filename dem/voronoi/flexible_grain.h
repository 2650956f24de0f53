#pragma once
// Finite-element mesh of flexible Voronoi grains (seed 004 §2.2-2.3;
// docs/voronoi.md, "Flexible grains").
//
// Each non-empty Laguerre cell is triangulated from its vertices and its
// centroid (seed 004 §2.3, Fig. 1): one triangle (centroid, v_k, v_k+1) per
// cell edge. The triangles are constant-strain elements of the grain's
// plane-strain E, nu; masses are lumped, a third of each triangle's mass to
// each of its nodes. Grains do not share nodes: node 0 of grain c is its
// centroid node (the node the contact circle is attached to), nodes 1..k its
// cell vertices in counter-clockwise order.
//
// Large displacements (seed 004 §2.1 keeps DEM's finite displacements and
// rotations): the element is total Lagrangian with the Saint Venant-Kirchhoff
// law, F = sum_a x_a (x) grad N_a (reference gradients), Green strain
// E = (F^T F - I) / 2, S = lambda tr(E) I + 2 mu E (plane-strain Lame
// constants), nodal forces f_a = -A_0 t F S grad N_a. A rigid motion gives
// no force; for small strains it is the linear plane-strain CST.
//
// Shape functions (seed 004 eq. for the triangular shape functions): the
// barycentric coordinates N_m = A_m / A of a point in the current triangle,
// used to interpolate the contact velocity at a local contact point and to
// return its force to the nodes (f_m = N_m f).
#include "dem/voronoi/tessellation.h"

#include <string>
#include <vector>

namespace demfem::dem::voronoi
{
  /// Elastic grain material (plane strain).
  struct GrainElasticity
  {
    double youngs_modulus = 0; ///< E [Pa]
    double poisson_ratio  = 0; ///< nu, in [0, 0.5)
    double density        = 0; ///< rho [kg/m^3]
    double thickness      = 1; ///< out-of-plane thickness t [m]

    /// Plane-strain Lame constants.
    double lame_lambda() const
    {
      return youngs_modulus * poisson_ratio /
             ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
    }
    double shear_modulus() const { return youngs_modulus / (2 * (1 + poisson_ratio)); }
    void   validate(const std::string &where) const;
  };

  class FlexibleGrainMesh
  {
  public:
    /// Meshes every non-empty cell of `tess`.
    FlexibleGrainMesh(const Tessellation &tess, const GrainElasticity &material);

    int n_grains() const { return static_cast<int>(grain_node_offset.size()) - 1; }
    int n_nodes() const { return static_cast<int>(x0.size()); }
    int n_triangles() const { return static_cast<int>(triangle_area0.size()); }

    /// Adds the internal (elastic) nodal forces at the current node
    /// positions (x, y) to (fx, fy); returns the strain energy. Allocation
    /// free.
    double add_internal_forces(const double *x, const double *y, double *fx,
                               double *fy) const;

    /// Deformation gradient of triangle e at the current positions,
    /// row-major F = {F_xX, F_xY, F_yX, F_yY}.
    void deformation_gradient(int e, const double *x, const double *y, double F[4]) const;
    /// Second Piola-Kirchhoff stress {S_xx, S_yy, S_xy} of triangle e.
    void second_piola_kirchhoff(int e, const double *x, const double *y,
                                double S[3]) const;

    /// Barycentric shape functions N[3] of triangle e at (px, py) in the
    /// current configuration (sum 1; all in [0, 1] inside the triangle).
    void shape_functions(int e, const double *x, const double *y, double px, double py,
                         double N[3]) const;
    /// Triangle of grain c containing (px, py) in the current configuration,
    /// or, if none does (a point just outside the deformed cell), the one
    /// whose smallest shape function is largest.
    int locate(int c, const double *x, const double *y, double px, double py) const;

    /// Stable time step of the explicit scheme (central differences):
    /// min over triangles of h / c_p, h the smallest height, c_p the
    /// plane-strain P-wave speed sqrt((lambda + 2 mu) / rho).
    double critical_time_step() const;

    // ---- per grain (cell index) -------------------------------------------
    std::vector<int> grain_node_offset;     ///< nodes of c: [off[c], off[c+1])
    std::vector<int> grain_triangle_offset; ///< triangles of c

    // ---- per node -----------------------------------------------------------
    std::vector<double> x0, y0; ///< reference positions
    std::vector<double> mass;   ///< lumped mass
    std::vector<int>    node_grain;

    // ---- per triangle -------------------------------------------------------
    std::vector<int>    triangle_nodes; ///< 3 per triangle, counter-clockwise
    std::vector<double> triangle_area0; ///< reference area
    std::vector<double> dN_dX, dN_dY;   ///< 3 per triangle, reference gradients

    const GrainElasticity &material() const { return mat; }

  private:
    GrainElasticity mat;
    double          lambda = 0, mu = 0;
  };
} // namespace demfem::dem::voronoi
