#pragma once
// The pieces every VTK XML poly-data writer of dem/ uses (dem/io/vtk_output.cc,
// dem/voronoi/voronoi_vtk.cc): named data arrays and the atomic write
// (docs/architecture.md, "Outputs and run status": the file goes to
// `path.tmp` and is renamed, so a failed run never leaves a partial file).
// Includes VTK: only writer translation units include it.
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <string>

namespace demfem::dem::vtkout
{
  /// A double array `name` of n tuples with `components` components.
  vtkSmartPointer<vtkDoubleArray> double_array(const char *name, int components,
                                               vtkIdType n);
  /// An int array `name` of n single-component tuples.
  vtkSmartPointer<vtkIntArray> int_array(const char *name, vtkIdType n);
  /// Writes `data` as .vtp (appended, raw) to path.tmp and renames it to
  /// path; throws std::runtime_error when VTK cannot write.
  void write_polydata(const std::string &path, vtkPolyData *data);
} // namespace demfem::dem::vtkout
