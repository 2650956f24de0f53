#pragma once
// The parameters of `demfem tunnel` (docs/tunnel.md, "Parameters"), declared
// next to the command they configure; `demfem study` declares the same keys
// so that a tunnel file can be swept as it is (apps/study_prm.cc adds the
// `Study` subsection).
#include <deal.II/base/parameter_handler.h>

#include "coupling/tunnel_run.h"

namespace demfem::apps
{
  /// The keys of the tunnel .prm; 'DEM region/radius' accepts 'auto'.
  void declare_tunnel_parameters(dealii::ParameterHandler &prm);
  /// Reads them, each value checked where it enters (the key named); the
  /// physics as a whole is validated per run (TunnelParams::validate, after
  /// a study's sweep settings are applied). region.radius < 0 means 'auto'.
  coupling::TunnelParams read_tunnel_settings(dealii::ParameterHandler &prm);

  /// Checks that a material file named by `key` exists
  /// (dem/specimen/material_file.h reads it and names the file and its own
  /// key in its errors).
  void check_material_file(const std::string &key, const std::string &file);
} // namespace demfem::apps
