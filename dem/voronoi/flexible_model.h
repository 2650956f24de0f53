#pragma once
// Flexible Voronoi particle model (seed 004 §2.2-2.3; docs/voronoi.md,
// "Flexible grains"): grains meshed by dem/voronoi/flexible_grain.h,
// contacts as in the rigid model (dem/voronoi/rigid_contact.h: normal from
// the disk centres, reference point, Lobatto points on the shared cell edge,
// bilinear-softening law per point), with the grains' FE discretisation in
// the kinematics:
//  - each grain's contact disk is rigidly attached to its centroid node
//    (no rotational degree of freedom; seed 004 §2.2): disk centre =
//    centroid node + the offset at install;
//  - the relative velocity at a local contact point is interpolated from
//    the nodal velocities of the triangle of each grain that holds the
//    shared edge, v = sum_m N_m v_m (seed 004 eq. for the contact velocity),
//    and the point force goes back to the same nodes, f_m = N_m f (seed 004
//    eqs. for the nodal contact forces);
//  - per node m a = F + F_d with the local non-viscous damping
//    F_d = -alpha |F| sign(v) per component (seed 004 eqs. for the equation
//    of motion and damping), integrated by central differences.
// The triangle of each point is fixed at install (the edge's fan triangle;
// its shape functions are evaluated in the current configuration, so a
// point that drifts off the edge is extrapolated linearly). Detection of new
// contacts (seed 004: the nearest Voronoi edge of each grain) is not done.
//
// Boundary conditions of a rectangular specimen (dem/voronoi/boundary.h;
// docs/voronoi.md, "Boundary conditions"), as the rigid model's but on the
// nodes: platen points at the two nodes of a side edge and its middle
// (Lobatto; one point: the middle), the platen velocity against the nodes'
// interpolated velocity, kn = E_c / h in the deformability mode (h from the
// disk centre to the edge line); pressure p L t on the current edge, half
// to each of its nodes.
#include "dem/voronoi/boundary.h"
#include "dem/voronoi/flexible_grain.h"
#include "dem/voronoi/rigid_contact.h"
#include "dem/voronoi/tessellation.h"

#include <array>
#include <vector>

namespace demfem::dem::voronoi
{
  class FlexibleVoronoiModel
  {
  public:
    /// Grains of the non-empty cells of `tess`, disks (x, y, radius) of the
    /// tessellated packing, one contact per shared cell edge.
    FlexibleVoronoiModel(const Tessellation &tess, const std::vector<double> &x,
                         const std::vector<double> &y, const std::vector<double> &radius,
                         const GrainElasticity &grain_material,
                         const ContactMaterial &contact_material,
                         PointScheme            scheme = PointScheme::lobatto3);

    /// One central-difference step: forces at the current positions (and
    /// the contact increments from the current velocities), damping, then
    /// v += dt F / m and x += dt v. Fixed nodes keep zero velocity.
    void step(double dt);

    /// The force part of `step`: (fx, fy) = applied + internal + contact
    /// forces at the current positions, the contact increments from the
    /// current velocities times dt. Nodes do not move.
    void compute_forces(double dt);

    /// Time step estimate: min of the elements' h / c_p and of 2 sqrt(m / k)
    /// over the nodes touched by a contact point, k = max(kn, ks) A_i,
    /// times `safety` (an estimate: a node shares its springs and elements).
    double stable_time_step(double safety = 0.5) const;

    /// Current disk centre of grain c.
    double disk_x(int c) const { return x[centroid_node(c)] + disk_dx[c]; }
    double disk_y(int c) const { return y[centroid_node(c)] + disk_dy[c]; }
    int    centroid_node(int c) const { return mesh.grain_node_offset[c]; }

    /// Kinetic energy of the nodes.
    double kinetic_energy() const;

    int n_grains() const { return mesh.n_grains(); }

    // ---- boundary ---------------------------------------------------------
    /// A platen on `side` (bottom or top), points on every cell edge of that
    /// side; inactive until activate_platen (which zeroes its points).
    int  add_platen(Side side, PlatenLaw law, double friction = 0);
    void activate_platen(int platen);
    /// Traction (compression positive) on the cell edges of `side`.
    void set_pressure(Side side, double p) { pressure[static_cast<int>(side)] = p; }
    /// Length-weighted mean displacement (component 0: x, 1: y) of the
    /// nodes of the cell edges on `side` since install, and the same mean of
    /// their install coordinate (the flexible grain carries its strain to
    /// its boundary: the gauge is the side itself).
    double side_displacement(Side side, int component) const;
    double side_position(Side side, int component) const;

    struct BoundaryEdge
    {
      int    grain = -1, node0 = -1, node1 = -1; ///< counter-clockwise ends
      Side   side   = Side::bottom;
      double length = 0; ///< at install
      double h      = 0; ///< disk centre to the edge line, at install
    };
    std::vector<BoundaryEdge> boundary_edges;
    std::vector<Platen>       platens;
    // ---- platen points: a point is w0 node0 + (1 - w0) node1 of its edge --
    std::vector<int>        pp_node0, pp_node1;
    std::vector<double>     pp_w0, pp_area, pp_kn, pp_ks;
    std::vector<double>     pp_un, pp_wn, pp_fs, pp_dt, pp_ds, pp_fn;
    std::vector<PointCrack> pp_crack;

    FlexibleGrainMesh    mesh;
    RigidVoronoiContacts contacts; ///< contact geometry and law state

    // ---- per node -----------------------------------------------------------
    std::vector<double> x, y, vx, vy;   ///< current positions, velocities
    std::vector<double> fx, fy;         ///< forces of the last step (undamped)
    std::vector<double> fx_ext, fy_ext; ///< applied forces
    std::vector<char>   fixed;          ///< velocity held at zero

    double damping = 0; ///< local non-viscous damping alpha

    // ---- per grain ------------------------------------------------------------
    std::vector<double> disk_dx, disk_dy, disk_radius;

    // ---- per local contact point (same index as contacts' points) ----------
    std::vector<int> triangle_a, triangle_b;

  private:
    PointScheme           scheme;
    std::array<double, 4> pressure{}; ///< by Side
    void                  add_boundary_forces(double dt);
    /// Adds the contact forces to (fx, fy); dt scales the velocities into
    /// displacement increments.
    void add_contact_forces(double dt);
  };
} // namespace demfem::dem::voronoi
