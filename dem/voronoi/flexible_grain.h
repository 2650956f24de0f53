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
// boundary nodes in counter-clockwise order.
//
// Short cell edges (docs/voronoi.md, "Short cell edges"): the fan triangle
// of an edge of length l has a height of about l, so the element time step
// h / c_p collapses on the very short edges of a genesis packing. Cell
// vertices closer than min_edge_fraction x d_mean are merged into one
// boundary node (at the mean of the merged vertices), d_mean the mean
// equivalent diameter 2 sqrt(A / pi) of the tessellation's cells: one
// length for the whole tessellation, so the two cells of a shared edge see
// the same threshold and coarsen it alike (a per-cell scale would merge an
// edge on one side and keep it on the other). Merging is greedy, shortest
// edge first, re-measured after each merge, and keeps at least three
// boundary nodes and positive fan triangles. Only the FE mesh is coarsened:
// the contact geometry (edge lengths, Lobatto points, areas) stays the
// tessellation's, and points are carried by the triangle that holds them
// (`locate`, `stencil`). The lumped masses of a grain are scaled so that it
// keeps the mass rho t A of its cell (the coarse polygon cuts its corners,
// losing a fraction of a percent of the area).
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

  /// Mesh options of the flexible grains.
  struct FlexibleMeshOptions
  {
    /// Cell vertices closer than this fraction of the mean equivalent cell
    /// diameter are merged into one node (0: the full centroid fan). The
    /// default is the measured trade of docs/voronoi.md, "Short cell edges".
    double min_edge_fraction = 0.1;
    void   validate(const std::string &where) const;
  };

  /// A point of a grain carried by one of its triangles with fixed weights
  /// (the barycentric coordinates at install, possibly slightly outside
  /// [0, 1] for a point just outside a coarsened cell): x = sum w_i x_{n_i}.
  struct PointStencil
  {
    int    node[3] = {0, 0, 0};
    double w[3]    = {0, 0, 0};
    double x(const double *px) const
    {
      return w[0] * px[node[0]] + w[1] * px[node[1]] + w[2] * px[node[2]];
    }
  };

  class FlexibleGrainMesh
  {
  public:
    /// Meshes every non-empty cell of `tess`.
    FlexibleGrainMesh(const Tessellation &tess, const GrainElasticity &material,
                      const FlexibleMeshOptions &options = {});

    int n_grains() const { return static_cast<int>(grain_node_offset.size()) - 1; }
    int n_nodes() const { return static_cast<int>(x0.size()); }
    int n_triangles() const { return static_cast<int>(triangle_area0.size()); }

    /// Adds the internal (elastic) nodal forces at the current node
    /// positions (x, y) to (fx, fy); returns the strain energy. Allocation
    /// free.
    double add_internal_forces(const double *x, const double *y, double *fx,
                               double *fy) const;
    /// The same for the triangles of grain c only (they touch only its
    /// nodes, so grains can run in parallel).
    double add_grain_internal_forces(int c, const double *x, const double *y, double *fx,
                                     double *fy) const;

    /// Deformation gradient of triangle e at the current positions,
    /// row-major F = {F_xX, F_xY, F_yX, F_yY}.
    void deformation_gradient(int e, const double *x, const double *y, double F[4]) const;
    /// Second Piola-Kirchhoff stress {S_xx, S_yy, S_xy} of triangle e.
    void second_piola_kirchhoff(int e, const double *x, const double *y,
                                double S[3]) const;
    /// Cauchy stress sigma = F S F^T / det F of triangle e, {s_xx, s_yy,
    /// s_xy, s_zz} (tension positive); s_zz is the plane-strain out-of-plane
    /// stress lambda tr(E) / det F (F_zz = 1, E_zz = 0).
    void cauchy_stress(int e, const double *x, const double *y, double sigma[4]) const;

    /// Barycentric shape functions N[3] of triangle e at (px, py) in the
    /// current configuration (sum 1; all in [0, 1] inside the triangle).
    void shape_functions(int e, const double *x, const double *y, double px, double py,
                         double N[3]) const;
    /// Triangle of grain c containing (px, py) in the current configuration,
    /// or, if none does (a point just outside the deformed cell), the one
    /// whose smallest shape function is largest.
    int locate(int c, const double *x, const double *y, double px, double py) const;
    /// Stencil of the reference point (X, Y) of grain c: its triangle
    /// (`locate` in the reference configuration) and its barycentric
    /// coordinates there.
    PointStencil stencil(int c, double X, double Y) const;

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

    // ---- per tessellation vertex (its index e) --------------------------------
    std::vector<int> vertex_node; ///< the boundary node it was merged into

    /// Merge distance used: min_edge_fraction x mean equivalent cell diameter.
    double merge_distance = 0;

    const GrainElasticity &material() const { return mat; }

  private:
    GrainElasticity mat;
    double          lambda = 0, mu = 0;
    /// Adds the forces of triangle e; returns its strain energy.
    double triangle_forces(int e, const double *x, const double *y, double *fx,
                           double *fy) const;
  };
} // namespace demfem::dem::voronoi
