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
//    point, v = sum_m N_m v_m (seed 004 eq. for the contact velocity), and
//    the point force goes back to the same nodes, f_m = N_m f (seed 004
//    eqs. for the nodal contact forces);
//  - per node m a = F + F_d with the local non-viscous damping
//    F_d = -alpha |F| sign(v) per component (seed 004 eqs. for the equation
//    of motion and damping), integrated by central differences.
// The triangle of each point is fixed at install: the triangle of each
// grain that holds the point's install position (FlexibleGrainMesh::locate;
// with merged short edges a point need not lie on the fan triangle of its
// edge). Its shape functions are evaluated in the current configuration, so
// a point that drifts off the triangle is extrapolated linearly.
//
// New contacts (seed 004 §2: "If a new contact between two grains is found
// to occur, the Voronoi edge closest to the contact location is selected,
// in each grain"; docs/voronoi.md, "New contacts"): two grains not in
// contact whose disks overlap (the DEM criterion the seed keeps) get a
// frictional (unbonded) contact at the PCM point, its length the shorter of
// the two grains' mesh boundary edges nearest to that point
// (dem/voronoi/flexible_contact_detection.cc). The search
// (dem/voronoi/new_contact_search.h, shared with the rigid model) is a Verlet list
// over a uniform grid of the disk centres, rebuilt when a disk has moved
// more than half the skin; it runs serially at the start of compute_forces,
// in ascending pair order (thread-count independent). Pairs whose disks
// already overlap at install without sharing an edge get their contact at
// install, stress free like the installed contacts.
//
// Boundary conditions (dem/voronoi/boundary.h; docs/voronoi.md, "Boundary
// conditions"), as the rigid model's but carried by the nodes: every
// boundary point (the ends of a side edge of the tessellation, a platen
// point) is a PointStencil, fixed weights of the nodes of the triangle
// that holds it at install (the ends of an unmerged edge are its nodes).
// Rectangle platens: points at the ends and middle of each side edge
// (Lobatto; one point: the middle), the platen velocity against the
// points' interpolated velocity, kn = E_c / h in the deformability mode (h
// from the disk centre to the edge line); pressure p L t on the current
// edge between its interpolated ends, half to each. Disk platens
// (Brazilian test): the gap-based points of RigidVoronoiModel::
// add_disk_platen on the outline, at their interpolated positions.
//
// Threads (OpenMP, from parallel_threshold grains): the contacts run in
// parallel, each into its points' slots (force, shape functions); then each
// grain, in parallel, sets its nodes' forces to the applied ones, adds its
// triangles' internal forces and gathers its nodes' contact contributions
// from a CSR list in point order; the boundary points follow serially. No
// sum depends on the thread count, no allocation per step.
#include "dem/voronoi/boundary.h"
#include "dem/voronoi/flexible_grain.h"
#include "dem/voronoi/new_contact_search.h"
#include "dem/voronoi/rigid_contact.h"
#include "dem/voronoi/tessellation.h"

#include <array>
#include <cstdint>
#include <utility>
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
                         const GrainElasticity     &grain_material,
                         const ContactMaterial     &contact_material,
                         PointScheme                scheme       = PointScheme::lobatto3,
                         const FlexibleMeshOptions &mesh_options = {});

    /// One central-difference step: forces at the current positions (and
    /// the contact increments from the current velocities), damping, then
    /// v += dt F / m and x += dt v. Fixed nodes keep zero velocity.
    void step(double dt);

    /// The force part of `step`: (fx, fy) = applied + internal + contact
    /// forces at the current positions, the contact increments from the
    /// current velocities times dt. Nodes do not move.
    void compute_forces(double dt);

    /// Time step estimate: min of the elements' h / c_p and of 2 sqrt(m / k)
    /// over the nodes carrying a contact or platen point (weight > 0),
    /// k = max(kn, ks) A_i, times `safety` (an estimate: a node shares its
    /// springs and elements).
    double stable_time_step(double safety = 0.5) const;

    /// Current disk centre of grain c.
    double disk_x(int c) const { return x[centroid_node(c)] + disk_dx[c]; }
    double disk_y(int c) const { return y[centroid_node(c)] + disk_dy[c]; }
    int    centroid_node(int c) const { return mesh.grain_node_offset[c]; }

    /// Kinetic energy of the nodes.
    double kinetic_energy() const;

    // ---- new contacts (docs/voronoi.md, "New contacts") ---------------------
    /// Forms a contact for every pair of grains not in contact whose disks
    /// overlap at the current positions (compute_forces(dt) calls it first,
    /// with its dt: the new points' u_n starts at -U minus the increment of
    /// the current velocities over dt that the same call then adds, so the
    /// overlap is not counted twice). Returns the number of contacts formed.
    int detect_new_contacts(double dt);
    /// Contacts [0, n_installed_contacts) are the shared cell edges of the
    /// tessellation; the later ones formed between overlapping disks.
    int n_installed_contacts = 0;
    /// Verlet skin of the search as a fraction of the largest disk radius
    /// (read at each rebuild of the candidate list).
    double verlet_skin_fraction = 0.2;
    /// Rebuilds of the candidate list so far (the search's cost counter).
    int n_verlet_rebuilds = 0;
    /// Candidate pairs (a < b, ascending) of the last rebuild: disks within
    /// r_a + r_b + skin, not in contact then.
    const std::vector<std::pair<int, int>> &verlet_candidates() const
    {
      return search.candidates();
    }

    int n_grains() const { return mesh.n_grains(); }

    // ---- boundary ---------------------------------------------------------
    /// A platen on `side` (bottom or top), points on every cell edge of that
    /// side; inactive until activate_platen (which zeroes its points).
    int add_platen(Side side, PlatenLaw law, double friction = 0);
    /// Brazilian test: a flat frictional platen tangent to a disk specimen
    /// at the pole of `side`, points on the outline edges within
    /// `cone_degrees` of the pole (RigidVoronoiModel::add_disk_platen, with
    /// the points carried by the nodes).
    int  add_disk_platen(Side side, double friction, double cone_degrees = 30);
    void activate_platen(int platen);
    /// Current position of a point carried by the nodes.
    double point_x(const PointStencil &s) const { return s.x(x.data()); }
    double point_y(const PointStencil &s) const { return s.x(y.data()); }
    /// Traction (compression positive) on the cell edges of `side`.
    void set_pressure(Side side, double p) { pressure[static_cast<int>(side)] = p; }
    /// Length-weighted mean displacement (component 0: x, 1: y) of the
    /// ends of the cell edges on `side` since install (interpolated from
    /// the nodes), and the same mean of their install coordinate (the flexible grain
    /// carries its strain to its boundary: the gauge is the side itself).
    double side_displacement(Side side, int component) const;
    double side_position(Side side, int component) const;

    /// A boundary edge of the tessellation (a side edge of a rectangle, or
    /// any outline edge).
    struct BoundaryEdge
    {
      int          grain = -1;
      PointStencil end[2]; ///< counter-clockwise ends, carried by the nodes
      Side         side   = Side::bottom;
      double       length = 0; ///< at install
      double       h      = 0; ///< disk centre to the edge line, at install
    };
    std::vector<BoundaryEdge> boundary_edges; ///< rectangle sides, by side
    std::vector<BoundaryEdge> outline_edges;  ///< all boundary edges (side unused)
    std::vector<Platen>       platens;
    // ---- platen points ------------------------------------------------------
    std::vector<PointStencil> pp_stencil;
    std::vector<double>       pp_area, pp_kn, pp_ks;
    std::vector<double>       pp_un, pp_wn, pp_fs, pp_dt, pp_ds, pp_fn;
    std::vector<PointCrack>   pp_crack;

    FlexibleGrainMesh    mesh;
    RigidVoronoiContacts contacts; ///< contact geometry and law state

    // ---- per node -----------------------------------------------------------
    std::vector<double> x, y, vx, vy;   ///< current positions, velocities
    std::vector<double> fx, fy;         ///< forces of the last step (undamped)
    std::vector<double> fx_ext, fy_ext; ///< applied forces
    std::vector<char>   fixed;          ///< velocity held at zero

    double damping = 0; ///< local non-viscous damping alpha
    /// Contacts, grains and nodes run in parallel (OpenMP) from this many
    /// grains; the results do not depend on the thread count.
    int parallel_threshold = 1024;

    // ---- per grain ------------------------------------------------------------
    std::vector<double> disk_dx, disk_dy, disk_radius;

    // ---- per local contact point (same index as contacts' points) ----------
    std::vector<int> triangle_a, triangle_b;
    /// Last step: force on B (-F_n n + F_s t) and the shape functions of
    /// the point in A's and B's triangles, {N_a[3], N_b[3]}.
    std::vector<double> point_fx, point_fy, point_N;

  private:
    PointScheme           scheme;
    std::array<double, 4> pressure{}; ///< by Side
    /// Contact contributions of each node (CSR over nodes): 6 p + i, i < 3
    /// for node i of A's triangle of point p, 3 + i for B's, ascending.
    std::vector<int> node_point_offset, node_point;
    /// (Re)builds node_point_offset, node_point from triangle_a, triangle_b.
    void build_gather_lists();
    // ---- new-contact search (flexible_contact_detection.cc) -----------------
    NewContactSearch    search;           ///< shared with the rigid model
    std::vector<double> disk_cx, disk_cy; ///< current disk centres (search input)
    std::vector<char>   disk_active;      ///< meshed grains (empty cells have no disk)
    void                update_disk_centres();
    void                rebuild_verlet_list();
    /// Contacts for the overlapping candidates; at install stress free,
    /// later compressed by the overlap. Returns the number formed.
    int  form_new_contacts(bool at_install, double dt);
    void form_contact(int a, int b, bool at_install, double dt);
    void add_boundary_forces(double dt);
    /// Advances the contact points (dt scales the velocities into
    /// displacement increments) into point_fx, point_fy, point_N.
    void         update_contact_points(double dt);
    BoundaryEdge boundary_edge(const Tessellation &tess, int c, int e, double pcx,
                               double pcy) const;
  };
} // namespace demfem::dem::voronoi
