#pragma once
// Rigid Voronoi contact model (seed 004 §2.3 and §2.5, the rigid contact
// model it extends; docs/voronoi.md, "Rigid contact model").
//
// Two rigid grains A and B (disks of radii R_A, R_B, centres x_A, x_B, the
// Laguerre cells of a packing) interact through their shared cell edge:
//  - contact normal from the centres, n = (x_B - x_A) / d, d = |x_B - x_A|,
//    tangent t = k x n (seed 004 eq. for the unit normal);
//  - reference overlap U = R_A + R_B - d and reference point
//    x_r = x_A + (R_A - U / 2 + delta) n, where delta is the distance along
//    n from the point-contact-model (PCM) plane to the cell edge, fixed at
//    install (seed 004 eqs. for the reference overlap and point; delta = 0
//    puts x_r at the PCM contact point);
//  - local contact points x_i = x_r + s_i t (seed 004 eq. 11), s_i fixed at
//    install from the cell edge: Lobatto positions, the two edge ends and
//    the middle, with areas A/6, 2A/3, A/6, A = edge length x thickness
//    (seed 004 §2.5), or one point at x_r with area A (the PCM reduction of
//    seed 004 §2.3);
//  - per point the relative velocity of B with respect to A at x_i gives
//    the normal and shear increments (seed 004 eqs. for the increments), the
//    law of dem/voronoi/softening_law.h gives the point forces with
//    kn A_i and ks A_i = kn A_i / kappa, and the point force -F_n n + F_s t
//    acts on B at x_i (the opposite on A), giving force and moment on each
//    grain about its centre.
// Small-displacement closed forms of the three-point scheme on a centred
// edge of length L (s = -L/2, 0, L/2; derived in tests/voronoi): normal
// force kn A delta_n, shear force ks A delta_s, bending moment kn I theta
// with I = sum A_i s_i^2 = 2 (A/6)(L/2)^2 = t L^3 / 12, the second moment of
// the edge section (the Lobatto rule integrates s^2 exactly).
//
// Storage: structure of arrays over contacts and over their points (CSR
// offsets); `update` allocates nothing once sized. `update_contacts` runs
// the contacts in parallel into per-contact results; `update` adds them to
// the grains in contact order (serial), RigidVoronoiModel gathers them per
// grain in parallel (dem/voronoi/rigid_model.h).
#include "dem/voronoi/softening_law.h"
#include "dem/voronoi/tessellation.h"

#include <vector>

namespace demfem::dem::voronoi
{
  /// Where the local contact points of a contact go.
  enum class PointScheme
  {
    lobatto3,       ///< edge ends and middle, areas A/6, 2A/3, A/6
    reference_point ///< one point at the reference point, area A
  };

  /// Current state of the rigid grains (arrays indexed by grain; the grain
  /// index is the tessellation's cell index).
  struct GrainKinematics
  {
    const double *x = nullptr, *y = nullptr;   ///< centres
    const double *radius = nullptr;            ///< disk radii
    const double *vx = nullptr, *vy = nullptr; ///< velocities
    const double *omega = nullptr;             ///< angular velocities (about +z)
  };

  /// Force accumulators of the grains (the update adds to them).
  struct GrainForces
  {
    double *fx = nullptr, *fy = nullptr, *mz = nullptr;
  };

  class RigidVoronoiContacts
  {
  public:
    explicit RigidVoronoiContacts(const ContactMaterial &material);

    /// One contact per shared edge of the tessellation (cells i < j), its
    /// points by `scheme`; disks (x, y, radius) are the tessellated packing.
    void add_from_tessellation(const Tessellation &tess, const std::vector<double> &x,
                               const std::vector<double> &y,
                               const std::vector<double> &radius, PointScheme scheme);

    /// One contact between grains a and b whose shared edge runs from
    /// (ex0, ey0) to (ex1, ey1); the disks are (xa, ya, ra) and (xb, yb, rb).
    /// Returns the contact index.
    int add_contact(int a, int b, double xa, double ya, double ra, double xb, double yb,
                    double rb, double ex0, double ey0, double ex1, double ey1,
                    PointScheme scheme);

    /// Advances all contacts by one step of length dt with the grains'
    /// current positions and velocities and adds the contact forces and
    /// moments to `forces`.
    void update(const GrainKinematics &grains, double dt, const GrainForces &forces);
    /// The per-contact part of `update`: advances all contacts and stores
    /// each contact's force on B and moments on A and B (contact_fx, ...),
    /// in parallel over contacts (OpenMP, from parallel_threshold contacts;
    /// thread-count independent); the caller gathers them per grain.
    void update_contacts(const GrainKinematics &grains, double dt);

    int n_contacts() const { return static_cast<int>(grain_a.size()); }
    int n_points() const { return static_cast<int>(s.size()); }

    /// Current reference point and normal of contact c (from the grains'
    /// positions).
    void reference_frame(int c, const GrainKinematics &grains, double &xr, double &yr,
                         double &nx, double &ny) const;

    /// Law constants of contact c (per contact: in the deformability mode
    /// of ContactMaterial kn = E_c / d depends on the contact).
    const SofteningCoefficients &coefficients(int c) const { return law[c]; }
    double                       thickness() const { return material.thickness; }
    const ContactMaterial       &contact_material() const { return material; }

    // ---- per contact -----------------------------------------------------
    std::vector<int>    grain_a, grain_b;
    std::vector<double> offset;      ///< delta: cell edge minus PCM plane, along n
    std::vector<double> edge_length; ///< L at install
    std::vector<int> point_offset; ///< points of c: [point_offset[c], point_offset[c+1])
    std::vector<SofteningCoefficients> law; ///< law constants (kn = E_c / d at install)

    // ---- per local contact point -----------------------------------------
    std::vector<double>     s;    ///< tangential coordinate from the reference point
    std::vector<double>     area; ///< A_i
    std::vector<double>     un, wn, fs, damage_t, damage_s; ///< law state
    std::vector<PointCrack> crack;
    std::vector<double>     fn; ///< normal force of the last update (> 0 tension)

    // ---- per contact, last update: force on B, moments about the centres --
    std::vector<double> contact_fx, contact_fy, contact_ma, contact_mb;
    int                 parallel_threshold = 8192; ///< contacts; below: serial

  private:
    ContactMaterial material;
  };
} // namespace demfem::dem::voronoi
