#pragma once
// Boundary conditions of a rectangular Voronoi specimen, shared by the rigid
// and the flexible model (docs/voronoi.md, "Boundary conditions"): the sides
// of the rectangle, the cell edges on them, and rigid platens on the bottom
// and top sides whose local contact points follow the grains' law.
#include "dem/voronoi/softening_law.h"
#include "dem/voronoi/tessellation.h"

#include <vector>

namespace demfem::dem::voronoi
{
  /// A side of a rectangular specimen.
  enum class Side : int
  {
    bottom = 0,
    right  = 1,
    top    = 2,
    left   = 3
  };

  /// Contact law of a platen's points.
  enum class PlatenLaw
  {
    frictional, ///< no tension, Coulomb friction (compression platens)
    glued       ///< linear in tension, compression and shear (tension grips)
  };

  /// A cell edge on a side of the rectangle: tessellation edge `edge` of
  /// cell `cell` (from vertex edge to the next vertex, counter-clockwise).
  struct SideEdge
  {
    int  cell = -1, edge = -1;
    Side side = Side::bottom;
  };

  /// The boundary edges of `tess` whose two ends lie on one side of the
  /// bounding box of all cell vertices (for a rectangular clip domain that
  /// box is the domain; edges of a circle domain are not listed), with the
  /// box.
  std::vector<SideEdge> rectangle_side_edges(const Tessellation &tess, double &xmin,
                                             double &ymin, double &xmax, double &ymax);

  /// A rigid platen on the bottom or top side (its points are stored by the
  /// model that owns it).
  struct Platen
  {
    Side      side   = Side::bottom;
    PlatenLaw law    = PlatenLaw::frictional;
    bool      active = false;
    double    nx = 0, ny = 0; ///< outward normal of the side (grain -> platen)
    double    vx = 0, vy = 0; ///< velocity
    double    ux = 0, uy = 0; ///< displacement since install
    double    fx = 0, fy = 0; ///< force of the grains on the platen, last step
    SofteningCoefficients frictional_law;                 ///< unbonded: friction only
    int                   point_begin = 0, point_end = 0; ///< its points
    /// Gap-based platen of a disk specimen (Brazilian test): points on the
    /// outline touch the plane n.x = plane + n.u only where they reach it.
    bool   gap      = false;
    double plane    = 0; ///< install position of the plane along n
    double friction = 0;
  };

  /// A platen on `side` (bottom or top) with the frictional law of
  /// `friction`; throws InputError for another side or a negative friction.
  Platen make_platen(Side side, PlatenLaw law, double friction);

  /// Advances one platen point by the increments (d_un opening, d_us shear
  /// of the platen relative to the grain) and returns its normal force (> 0
  /// tension): glued, linear kn A, ks A; frictional, the no-strength
  /// (linear no-tension Coulomb) law of dem/voronoi/softening_law.h.
  inline double update_platen_point(const Platen &p, double kn, double ks, double A,
                                    double d_un, double d_us, PointState s)
  {
    if (p.law == PlatenLaw::glued)
      {
        s.un += d_un;
        s.fs -= ks * A * d_us;
        return kn * A * s.un;
      }
    SofteningCoefficients k = p.frictional_law;
    k.kn                    = kn;
    k.ks                    = ks;
    return update_point(k, A, d_un, d_us, s);
  }

  /// Advances one point of a gap-based (disk) platen by its penetration of
  /// the platen plane and the shear increment d_us; returns its normal
  /// force (<= 0): kn A x penetration while in touch, with an incremental
  /// Coulomb shear force fs (platen friction); apart, no force.
  inline double update_gap_point(const Platen &p, double kn, double ks, double A,
                                 double penetration, double d_us, double &fs)
  {
    if (!(penetration > 0))
      {
        fs = 0;
        return 0;
      }
    const double f_n   = -kn * A * penetration;
    const double trial = fs - ks * A * d_us;
    const double cap   = -p.friction * f_n;
    fs                 = trial > cap ? cap : trial < -cap ? -cap : trial;
    return f_n;
  }
} // namespace demfem::dem::voronoi
