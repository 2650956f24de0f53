#pragma once
// The material file (material.json of `demfem calibrate`, docs/calibrate.md):
// reads its "microparameters" block back into MaterialParams, so that every
// consumer (the benchmark scene, the tunnel region) builds the material the
// calibration measured, with all its distributions. The writer is
// apps/calibrate_run.cc (`microparameters`); the key names are PFC's.
#include "dem/specimen/material.h"

#include <string>

namespace demfem::dem
{
  /// What a material file holds besides the microparameters.
  struct MaterialFile
  {
    int            dim = 2;
    MaterialParams material;
  };

  /// Reads `path`; InputError naming the file and the key for a missing or
  /// ill-typed entry, and the material's own validation (ranges).
  MaterialFile read_material_file(const std::string &path);

  /// A top-level number of a material file (e.g. "E", "nu", "ucs"):
  /// InputError naming the file and the key when it is missing or not a
  /// number; a key that is not `required` gives NaN when absent or null.
  double read_material_number(const std::string &path, const std::string &key,
                              bool required = true);
} // namespace demfem::dem
