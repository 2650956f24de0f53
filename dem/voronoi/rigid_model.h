#pragma once
// Rigid Voronoi particle model (seed 004 §2.2 with rigid grains, the rigid
// model the seed extends; docs/voronoi.md, "Rigid grains"): the grains are
// the non-empty Laguerre cells of a disk packing, rigid bodies with three
// degrees of freedom each, interacting through RigidVoronoiContacts (one
// contact per shared cell edge).
//
// Reference point of a grain: its disk centre, the point the contact model
// takes its normals, reference points and moments from
// (dem/voronoi/rigid_contact.h). Mass rho t A_cell; polar moment of inertia
// of the cell polygon about the disk centre (parallel-axis term included).
// The diagonal mass matrix about the disk centre rather than the centroid is
// exact for statics (equilibrium of forces and of moments about any point)
// and neglects the translation-rotation coupling m (c - x) of the dynamics;
// the lab tests are quasi-static (docs/voronoi.md).
//
// Motion per degree of freedom, as dem/engine/model.cc: F_d = F - alpha |F|
// sign(v) (local non-viscous damping, seed 004 §2.2), v += dt F_d / m,
// x += dt v (central differences / velocity Verlet with the contact
// increments from the current velocities).
//
// Boundary conditions of a specimen clipped to a rectangle (docs/voronoi.md,
// "Boundary conditions"):
//  - platens: rigid straight walls on the bottom and top sides; each cell
//    edge on the side gets local contact points (same scheme as the grain
//    contacts) with the kn A law, frictional (no tension, Coulomb) or glued
//    (linear, no strength; direct tension grips). The platen is grain B,
//    the normal the outward normal of the side, the reference point the
//    foot of the disk centre on the edge line, fixed distance h; in the
//    deformability mode kn = E_c / h (the half spring of a cell whose
//    neighbour is rigid, which keeps the network elastically uniform);
//  - pressure: a traction p (compression positive) on the cell edges of
//    chosen sides, force p L t along the inward normal of the current
//    (rotated) edge, at its current middle;
//  - disk platens (Brazilian test on a circular specimen): flat platens
//    tangent at the poles, gap-based points on the outline (add_disk_platen).
//
// New contacts (seed 004 §2: "If a new contact between two grains is found
// to occur, the Voronoi edge closest to the contact location is selected,
// in each grain"; docs/voronoi.md, "New contacts"), as in the flexible
// model (dem/voronoi/flexible_model.h) and with the same search
// (dem/voronoi/new_contact_search.h): two grains not in contact whose disks
// overlap get a frictional (unbonded) contact at the PCM point, its length
// the shorter of the two grains' cell edges (the cell polygon moved and
// turned with its grain) nearest to that point, its normal force kn A times
// the overlap (dem/voronoi/rigid_contact_detection.cc). The search runs
// serially at the start of compute_forces, in ascending pair order; pairs
// whose disks overlap at install without a shared edge get their contact at
// install, stress free like the installed ones.
//
// Threads: contacts into per-contact slots, then a per-grain gather in
// contact order, so the results do not depend on the thread count.
#include "dem/voronoi/boundary.h"
#include "dem/voronoi/new_contact_search.h"
#include "dem/voronoi/rigid_contact.h"
#include "dem/voronoi/tessellation.h"

#include <array>
#include <utility>
#include <vector>

namespace demfem::dem::voronoi
{
  class RigidVoronoiModel
  {
  public:
    /// A cell edge on a side of the rectangular domain.
    struct BoundaryEdge
    {
      int    grain = -1;
      Side   side  = Side::bottom;
      double rx0 = 0, ry0 = 0, rx1 = 0, ry1 = 0; ///< ends from the disk centre, install
      double length = 0;
    };
    /// Grains of the non-empty cells of `tess` (disks x, y, radius of the
    /// tessellated packing), density rho; one contact per shared edge. The
    /// boundary edges of a rectangular `tess` domain are sorted by side.
    RigidVoronoiModel(const Tessellation &tess, const std::vector<double> &x,
                      const std::vector<double> &y, const std::vector<double> &radius,
                      double density, const ContactMaterial &contact_material,
                      PointScheme scheme = PointScheme::lobatto3);

    int n_grains() const { return static_cast<int>(x.size()); }

    /// One step: compute_forces, then damping and central differences;
    /// platens move with their velocities.
    void step(double dt);
    /// Forces (fx, fy, mz) at the current positions: applied + pressure +
    /// grain contacts + platen contacts, the contact increments from the
    /// current velocities times dt. Nothing moves. New contacts first
    /// (detect_new_contacts). Allocation free except when a contact forms
    /// or the search's candidate list is rebuilt.
    void compute_forces(double dt);

    /// Time step estimate: safety * 2 / sqrt(max over grains of
    /// 2 (K_t / m + K_r / I)), K_t = sum of max(kn, ks) A_i over the grain's
    /// points (grain and platen contacts), K_r = sum of max(kn, ks) A_i r_i^2
    /// with r_i the arm from the disk centre, at most the cell's reach (the
    /// farthest cell vertex: a separated contact's points lie far outside
    /// the cells) (a Gershgorin-type bound of the largest eigenfrequency: a
    /// grain vibrating against neighbours that move the opposite way).
    double stable_time_step(double safety = 0.5) const;

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
    /// Candidate pairs (a < b, ascending) of the last rebuild.
    const std::vector<std::pair<int, int>> &verlet_candidates() const
    {
      return search.candidates();
    }

    // ---- boundary ---------------------------------------------------------
    /// Adds a platen on `side` (bottom or top): points on every boundary edge
    /// of that side. Inactive until `activate_platen`.
    int add_platen(Side side, PlatenLaw law, double friction = 0);
    /// Brazilian test (docs/voronoi.md, "Boundary conditions"): a flat
    /// frictional platen on `side` (bottom or top) of a disk specimen,
    /// tangent to its outline at install. Points: the ends and middle of
    /// every outline edge (Lobatto areas) within `cone_degrees` of the pole,
    /// attached to their grains (turning with them); a point pushes on the
    /// platen with kn A_i times its penetration of the plane, a Coulomb
    /// shear force while in touch, nothing when apart.
    int add_disk_platen(Side side, double friction, double cone_degrees = 30);
    /// Current arm from the disk centre of platen point i of platen k.
    void platen_point_arm(int k, int i, double &rx, double &ry) const;
    /// Starts the platen's contact points from zero force (the incremental
    /// law needs no platen position: it moves with the grains' faces).
    void activate_platen(int platen);
    /// Grain forces on platen k (the platen reaction is the opposite).
    double platen_force_x(int k) const { return platens[k].fx; }
    double platen_force_y(int k) const { return platens[k].fy; }

    /// Traction (compression positive) on the boundary edges of `side`.
    void   set_pressure(Side side, double p) { pressure[static_cast<int>(side)] = p; }
    double pressure_on(Side side) const { return pressure[static_cast<int>(side)]; }
    /// Force (Fx, Fy) of the pressure on boundary edge e and the arm of its
    /// point of application (the current edge middle) from the disk centre.
    void pressure_force(const BoundaryEdge &e, double &Fx, double &Fy, double &rx,
                        double &ry) const;

    /// Strain gauge of a side: mean displacement since install (component
    /// 0: x, 1: y) of the disk centres of the grains with an edge on `side`,
    /// weighted by the edge length, and the same mean of their install
    /// coordinate. A rigid grain carries its boundary edge without any
    /// spring between the centre and the edge, so a lateral strain is
    /// (u_right - u_left) / (X_right - X_left) over these centres; the edge
    /// middles would see the strain of the springs over the width W and
    /// underestimate it by the boundary half-cells (about d / W).
    double side_displacement(Side side, int component) const;
    double side_position(Side side, int component) const;

    // ---- per grain (index: cell; empty cells are inert: mass 0, held) ------
    std::vector<double> x, y, theta;    ///< disk centre, rotation since install
    std::vector<double> x0, y0;         ///< disk centre at install
    std::vector<double> radius;         ///< disk radius
    std::vector<double> vx, vy, omega;  ///< velocities
    std::vector<double> fx, fy, mz;     ///< forces of the last step (undamped)
    std::vector<double> fx_ext, fy_ext; ///< applied forces
    std::vector<double> mz_ext;         ///< applied moments
    std::vector<double> mass, inertia;  ///< rho t A, polar moment about the disk centre
    std::vector<char>   held;           ///< velocities held at zero (empty cells)
    /// Cell polygon of each grain (CSR over grains; none for empty cells):
    /// counter-clockwise vertices from the disk centre at install; current
    /// vertex = centre + R(theta) (cell_rx, cell_ry).
    std::vector<int>    cell_offset;
    std::vector<double> cell_rx, cell_ry;

    RigidVoronoiContacts contacts;
    double               damping = 0.7; ///< local non-viscous damping alpha
    double               time    = 0;
    /// Grains: the gather of contact forces and the motion run in parallel
    /// (OpenMP) from this many grains; the results do not depend on the
    /// thread count (each grain sums its contacts in contact order).
    int parallel_threshold = 4096;

    std::vector<BoundaryEdge> boundary_edges; ///< rectangular domain, by side
    std::vector<BoundaryEdge> outline_edges;  ///< all boundary edges (side unused)

    // ---- platens ------------------------------------------------------------
    std::vector<Platen> platens;

    // ---- platen points --------------------------------------------------------
    std::vector<int>        pp_grain;
    std::vector<double>     pp_h, pp_s, pp_area; ///< normal arm, tangential s, area
    std::vector<double>     pp_rx, pp_ry; ///< gap platens: arm from the centre, install
    std::vector<double>     pp_kn, pp_ks; ///< per unit area
    std::vector<double>     pp_un, pp_wn, pp_fs, pp_dt, pp_ds, pp_fn;
    std::vector<PointCrack> pp_crack;

  private:
    /// Contacts of each grain (CSR over grains): entry 2 c + 1 if the grain
    /// is the contact's B, 2 c if it is A, ascending c.
    std::vector<int> grain_contact_offset, grain_contact;
    /// (Re)builds grain_contact_offset, grain_contact from the contacts.
    void build_grain_contact_lists();
    // ---- new-contact search (rigid_contact_detection.cc) --------------------
    NewContactSearch  search;   ///< shared with the flexible model
    std::vector<char> has_cell; ///< grains with a disk in the model
    void              rebuild_verlet_list();
    /// Contacts for the overlapping candidates; at install stress free,
    /// later compressed by the overlap. Returns the number formed.
    int                   form_new_contacts(bool at_install, double dt);
    void                  form_contact(int a, int b, bool at_install, double dt);
    PointScheme           scheme;
    std::array<double, 4> pressure{}; ///< by Side
    void                  add_pressure_forces();
    void                  add_platen_forces(double dt);
  };

  /// Polar moment of inertia per unit mass-area density (integral of
  /// |x - p|^2 over the polygon) of a counter-clockwise polygon about p.
  double polygon_polar_moment(const double *vx, const double *vy, int n, double px,
                              double py);
} // namespace demfem::dem::voronoi
