#pragma once
// Laguerre (power) tessellation of a 2D packing of disks, clipped to the
// specimen boundary (docs/voronoi.md, "Tessellation"; seed 004 §2.3: the
// grains of the Voronoi particle model are the Laguerre cells of the
// packing, the contact of two grains is their shared cell edge).
//
// The power distance of a point x to disk i (centre p_i, radius R_i) is
// |x - p_i|^2 - R_i^2; the cell of disk i is the set of points of the
// specimen no farther from disk i than from any other disk in that sense.
// The combinatorics (which cells are neighbours, which disks have empty
// cells) comes from CGAL's 2D regular triangulation, the dual of the power
// diagram, built in tessellation.cc only: no CGAL type appears here, so
// translation units that use the result do not compile CGAL.
//
// Output layout: structure of arrays, per cell index ranges (CSR offsets)
// into flat arrays of polygon vertices and of cell edges.
#include <string>
#include <vector>

namespace demfem::dem::voronoi
{
  /// The specimen outline the cells are clipped to: an axis-aligned
  /// rectangle, or a circle approximated by a regular polygon inscribed in it
  /// (then the domain area is that of the polygon).
  struct ClipDomain
  {
    enum class Shape
    {
      rectangle,
      circle
    };
    Shape  shape = Shape::rectangle;
    double xmin = 0, ymin = 0, xmax = 1, ymax = 1; ///< rectangle
    double cx = 0, cy = 0, radius = 1;             ///< circle
    int    circle_sides = 256;                     ///< circle: polygon sides

    static ClipDomain rectangle(double xmin, double ymin, double xmax, double ymax);
    static ClipDomain circle(double cx, double cy, double radius, int sides = 256);

    /// Counter-clockwise vertices of the clipping polygon.
    void polygon(std::vector<double> &x, std::vector<double> &y) const;
    /// Area of the clipping polygon (shoelace formula).
    double area() const;
    /// Throws InputError for a degenerate outline.
    void validate(const std::string &where) const;
  };

  /// Why a disk has no cell.
  enum class EmptyCellReason : int
  {
    none           = 0, ///< the cell is not empty
    hidden         = 1, ///< hidden by the weights: power cell empty (or duplicate centre)
    outside_domain = 2  ///< power cell does not intersect the clip domain
  };

  /// Clipped Laguerre tessellation. Cell c belongs to disk c of the input.
  /// Cell polygons are convex and counter-clockwise. Edge e of cell c runs
  /// from polygon vertex e to vertex e+1 (cyclically) and is shared with
  /// cell `edge_neighbour[e]`, or lies on the domain boundary
  /// (`edge_neighbour[e] == boundary`).
  struct Tessellation
  {
    static constexpr int boundary = -1;

    int n_cells() const { return static_cast<int>(area.size()); }

    // ---- per cell --------------------------------------------------------
    std::vector<double>          area;       ///< cell area
    std::vector<double>          centroid_x; ///< area centroid (the disk centre if empty)
    std::vector<double>          centroid_y;
    std::vector<EmptyCellReason> empty_reason;
    /// Cell c's vertices and edges are [offset[c], offset[c+1]) of the flat
    /// arrays below (a polygon with k vertices has k edges).
    std::vector<int> offset;

    // ---- per polygon vertex / per edge (same index) ----------------------
    std::vector<double> vertex_x; ///< polygon vertex e of its cell
    std::vector<double> vertex_y;
    std::vector<int>    edge_neighbour; ///< cell across edge e, or boundary
    std::vector<double> edge_length;    ///< |vertex e+1 - vertex e|

    /// Disks whose cell is empty (hidden or outside the domain), ascending.
    std::vector<int> empty_cells;

    /// Index range of cell c's vertices/edges.
    int begin(int c) const { return offset[c]; }
    int end(int c) const { return offset[c + 1]; }
    /// Index of the vertex following vertex e within its cell (cyclic).
    int next(int c, int e) const { return e + 1 < offset[c + 1] ? e + 1 : offset[c]; }
    /// Edge of cell c shared with cell d, or -1.
    int shared_edge(int c, int d) const;
  };

  /// Edges shorter than this fraction of the domain diameter are dropped as
  /// degenerate (four or more cells meeting in a point, e.g. a square
  /// lattice, give zero-length edges through roundoff).
  constexpr double degenerate_edge_fraction = 1e-10;

  /// Laguerre tessellation of the disks (x[i], y[i], radius[i]) with the
  /// weights radius^2, clipped to `domain`. Disks with empty cells are
  /// reported in `empty_cells` (area 0, no vertices), not rejected. Throws
  /// InputError for mismatched array sizes, negative or non-finite radii or
  /// coordinates, or an invalid domain.
  Tessellation laguerre_tessellation(const std::vector<double> &x,
                                     const std::vector<double> &y,
                                     const std::vector<double> &radius,
                                     const ClipDomain          &domain);
} // namespace demfem::dem::voronoi
