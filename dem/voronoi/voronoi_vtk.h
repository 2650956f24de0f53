#pragma once
// VTK XML output of rigid and flexible Voronoi grains (docs/voronoi.md,
// "VTK output"),
// written with the VTK library like dem/io/vtk_output.cc, each file to
// `path.tmp` and renamed (docs/architecture.md, "Outputs and run status"):
//  - cells: the grain polygons in the current configuration (the install
//    polygon moved with its grain), cell data grain id, displacement and
//    rotation of the disk centre, and the grain's mean stress
//    (Love-Weber: sum of arm x force over the cell area and thickness, from
//    the grain and platen contact points and the boundary pressure);
//  - points: the local contact points (grain contacts), point data D_t,
//    D_s, crack state (0 intact, 1 tensile, 2 shear, 3 unbonded), normal
//    force F_n (> 0 tension), shear force F_s, the two grains;
//  - cracks: one line segment per cracked local point, the piece of the
//    cell edge the point stands for (Lobatto: the end sixths and the middle
//    two thirds; one point: the whole edge), cell data mode (1 tensile,
//    2 shear) and the two grains.
// Flexible grains: the cells are the element triangles in the current
// configuration (points: the nodes, point data displacement), cell data
// grain id, Cauchy stress sigma = F S F^T / det F (xx, yy, xy; tension
// positive) and the mean stress (s_xx + s_yy + s_zz) / 3 with the
// plane-strain s_zz = lambda tr(E) / det F; the contact points and cracks
// as the rigid grains', at the reference points of the current disks.
#include "dem/voronoi/flexible_model.h"
#include "dem/voronoi/rigid_model.h"
#include "dem/voronoi/tessellation.h"

#include <string>

namespace demfem::dem::voronoi
{
  /// Grain polygons (.vtp). `tess` is the tessellation the model was built
  /// from.
  void write_voronoi_cells_vtk(const std::string &path, const Tessellation &tess,
                               const RigidVoronoiModel &model);
  /// Local contact points of the grain contacts (.vtp, vertices).
  void write_voronoi_points_vtk(const std::string &path, const RigidVoronoiModel &model);
  /// Cracked local points as edge pieces (.vtp, lines); returns their number.
  int write_voronoi_cracks_vtk(const std::string &path, const RigidVoronoiModel &model);

  /// Element triangles of flexible grains (.vtp).
  void write_voronoi_cells_vtk(const std::string          &path,
                               const FlexibleVoronoiModel &model);
  /// Local contact points of flexible grains (.vtp, vertices).
  void write_voronoi_points_vtk(const std::string          &path,
                                const FlexibleVoronoiModel &model);
  /// Cracked local points of flexible grains (.vtp, lines); their number.
  int write_voronoi_cracks_vtk(const std::string          &path,
                               const FlexibleVoronoiModel &model);

  /// Love-Weber mean stress {s_xx, s_yy, s_xy} of every grain (tension
  /// positive; zero for empty cells), from the forces of the last step.
  void voronoi_grain_stress(const Tessellation &tess, const RigidVoronoiModel &model,
                            std::vector<double> &sxx, std::vector<double> &syy,
                            std::vector<double> &sxy);
} // namespace demfem::dem::voronoi
