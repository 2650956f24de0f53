#pragma once
// Material vessels (fistPkg §4.1, Table 6): 2D box; 3D box (polyaxial cell)
// and cylinder (two planar walls and a triangulated cylinder wall). The
// axial direction is the last axis (y in 2D, z in 3D); H is measured along
// it, W along x, D along y (3D). Walls are expanded by the expansion factor
// so grains cannot escape when the walls move apart; walls interact only
// with grains, so their mutual overlap is irrelevant.
#include "dem/engine/walls.h"

#include <array>
#include <string>
#include <vector>

namespace demfem::dem
{
  struct VesselParams
  {
    std::string shape    = "box"; ///< "box" | "cylinder" (3D)
    double      H        = 0;     ///< height (axial) [m]
    double      W        = 0;     ///< width (x); cylinder: diameter [m]
    double      D        = 1;     ///< depth (y, 3D box); 2D: unit thickness
    double      expand   = 1.2;   ///< expansion factor (>= 1)
    double      inset_l  = 0.8;   ///< measurement regions span inset_l * max dimension
    double      inset_d  = 0.8;   ///< region diameter = inset_d * min dimension
    double      emod     = 0;     ///< E* of the grain-wall contacts [Pa]; 0: lnm_emod
    int         segments = 24;    ///< cylinder: facets around the circumference

    void validate(const std::string &where, int dim) const;
  };

  /// A spherical (3D) or circular (2D) measurement region.
  template <int dim>
  struct Region
  {
    Vec<dim> center = Vec<dim>::Zero();
    double   radius = 0;
    double   volume() const; ///< 2D: area (unit thickness)
  };

  template <int dim>
  struct Vessel
  {
    VesselParams params;
    /// Planar walls: lo[a], hi[a] are the wall ids bounding axis a (-1 if
    /// none: the lateral axes of the cylinder). side: cylinder wall id.
    std::array<int, dim> lo, hi;
    int                  side = -1;
    /// One vertex of each planar wall (its coordinate a gives the position)
    /// and the vertices of the cylinder wall.
    std::array<int, dim> lo_vertex, hi_vertex;
    std::vector<int>     side_vertices;
    Vec<dim>             center = Vec<dim>::Zero(); ///< vessel centre (origin at genesis)
    std::array<double, dim>    initial_length;      ///< lengths at creation
    std::array<Region<dim>, 3> regions; ///< three regions along the axial direction

    /// Flexible lateral walls (2D confined compression; docs/calibrate.md,
    /// "Confining servo"): the walls of lateral axis a as chains of vertices
    /// ordered along the axial axis, each vertex servo-controlled on its
    /// own; empty: the rigid wall of lo[a], hi[a].
    std::array<std::vector<int>, dim> lo_chain, hi_chain;

    bool cylinder() const { return side >= 0; }
    bool flexible(int a) const { return !lo_chain[a].empty(); }
    /// Replaces the rigid walls of lateral axis a (2D: a = 0) by flexible
    /// walls at the same places: `segments` facets of equal length between
    /// the platens and one more beyond each platen (the vessel's expansion
    /// factor). The rigid walls are parked `park` outward (their contacts
    /// end at the next contact detection), so facet indices of existing
    /// contacts stay valid.
    void make_flexible(Walls<dim> &w, int a, int segments, double park);
    /// Tributary length of each vertex of `chain` between the platens: the
    /// integral of its hat function over the platen gap (2D, unit depth:
    /// the area of the lateral boundary the vertex carries) [m^2].
    std::vector<double> tributary_areas(const Walls<dim>       &w,
                                        const std::vector<int> &chain) const;
    /// Current inner length along axis a (cylinder lateral: diameter;
    /// flexible walls: between their tributary-area weighted mean
    /// positions).
    double length(const Walls<dim> &w, int a) const;
    double radius(const Walls<dim> &w) const; ///< cylinder radius
    /// Current volume (2D: area x unit thickness).
    double volume(const Walls<dim> &w) const;
    /// Cross-section normal to axis a (2D: length of the other side x 1;
    /// cylinder lateral: axial length x diameter).
    double area(const Walls<dim> &w, int a) const;
    /// Wall-based normal stress along axis a (fistPkg Eq. 21, tension
    /// positive): mean of the forces that the grains exert on the two walls
    /// (pushed outward) over the current area; cylinder lateral (a < dim-1):
    /// radial pressure = total radial force / lateral area.
    double wall_stress(const Walls<dim> &w, int a) const;
    /// Wall-based strain along axis a (tension positive) since creation or
    /// the last reset_strain_reference.
    double wall_strain(const Walls<dim> &w, int a) const;
    void   reset_strain_reference(const Walls<dim> &w);
    /// Opposing walls of axis a move apart with speed v each (v < 0: closing).
    /// Cylinder lateral: radial speed of the cylinder wall.
    void set_velocity(Walls<dim> &w, int a, double v) const;
    /// Moves the walls of axis a outward by delta each (cylinder lateral:
    /// radius grows by delta). Used by finalization smoothing.
    void translate_outward(Walls<dim> &w, int a, double delta) const;
    /// Whether x lies inside the vessel (shrunk by margin).
    bool contains(const Walls<dim> &w, const Vec<dim> &x, double margin = 0) const;
  };

  /// Adds the vessel's walls to `walls` (centred at the origin).
  template <int dim>
  Vessel<dim> make_vessel(Walls<dim> &walls, const VesselParams &p,
                          const std::string &where = "vessel");
} // namespace demfem::dem
