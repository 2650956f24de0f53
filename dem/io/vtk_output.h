#pragma once
// VTK XML output of a DEM model for ParaView (docs/architecture.md, "VTK
// files"): particles as
// points (.vtp, Point Gaussian-ready: "radius" array), contacts/bonds as
// lines between the centres, cracks (fistPkg §3.4) as segments (2D) or
// disks drawn as polygons (3D), and .pvd collections of a time series.
// Every file is written to a temporary name and renamed over the target, so
// a failed run never leaves a partial file over a good one.
#include "dem/engine/model.h"

#include <string>
#include <vector>

namespace demfem::dem::vtkout
{
  /// Particles: points with arrays radius, velocity, displacement (x - x0),
  /// angular_velocity, group, id, fixity, and averaged_stress (3x3 tensor,
  /// tension positive: dem::grain_stresses with `solid_fraction`, the
  /// assembly's 1 - porosity, so that it reads as continuum stress).
  template <int dim>
  void write_particles(const std::string &path, const Model<dim> &model,
                       double solid_fraction = 1.0);

  /// Contacts: one line per ball-ball contact (ball-wall contacts go from the
  /// centre to the contact point) with arrays group, wall (0/1), active
  /// (0/1), bonded (fraction of bonded interface: flat-joint elements
  /// bonded / elements; 1 or 0 for contact and parallel bonds; 0 for linear),
  /// force (global, on piece 2), normal_force (Fn, tension positive), gap.
  template <int dim>
  void write_contacts(const std::string &path, const Model<dim> &model);

  /// Cracks: 2D a segment of length `size` centred on the crack position,
  /// perpendicular to the contact normal (it lies in the failed interface);
  /// 3D a disk of diameter `size` in the plane of the interface, drawn as a
  /// polygon with `disk_sides` sides. Arrays mode (0 tension, 1 shear), size,
  /// gap, step, normal.
  template <int dim>
  void write_cracks(const std::string &path, const std::vector<CrackRecord<dim>> &cracks,
                    int disk_sides = 12);

  /// A .pvd collection: entries hold paths relative to the .pvd's folder and
  /// times written with full precision (17 significant digits).
  class Collection
  {
  public:
    explicit Collection(std::string pvd_path)
        : path_(std::move(pvd_path))
    {
    }
    /// Records `file` (absolute or relative to the working directory) at
    /// `time`, stored relative to the .pvd, and rewrites the .pvd.
    void               add(double time, const std::string &file);
    void               write() const;
    const std::string &path() const { return path_; }

  private:
    std::string                                 path_;
    std::vector<std::pair<double, std::string>> entries_;
  };

  /// Writes `text` to `path` through a temporary file and a rename.
  void write_text_atomically(const std::string &path, const std::string &text);
} // namespace demfem::dem::vtkout
