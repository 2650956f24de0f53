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
#include "dem/voronoi/flexible_grain.h"
#include "dem/voronoi/rigid_contact.h"
#include "dem/voronoi/tessellation.h"

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
    /// Adds the contact forces to (fx, fy); dt scales the velocities into
    /// displacement increments.
    void add_contact_forces(double dt);
  };
} // namespace demfem::dem::voronoi
