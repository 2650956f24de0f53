#pragma once
// `demfem tunnel FILE.prm --probe` (docs/tunnel.md, "The probe"): is the
// region the calibrated material? The probe builds lab specimens with the
// region's genesis at the region's grain size (the calibration specimen of
// the material file scaled by the grain-size factor) and runs the UCS and
// Brazilian tests of the calibration, for several packing seeds.
#include "coupling/tunnel_run.h"

#include <ostream>
#include <string>

namespace demfem::apps
{
  /// E and nu of the probe's seed mean within this fraction of the
  /// material file's (the 5 %).
  inline constexpr double probe_elastic_tolerance = 0.05;

  /// Without a material file (the `DEM region` keys' material): the lab
  /// specimen's width in mean grain diameters (2D: about 1 900 grains in a
  /// box twice as high; 3D: a 10 x 20 x 10 box, about 2 300 spheres), and
  /// the UCS test's axial strain per time step. Measured on the breakable
  /// study example at a/d = 10 (docs/tunnel.md, "The probe"): 7e-8 per step
  /// read E 2 % below 1.8e-8 per step, nu and UCS within 0.3 %; 2e-8 reaches
  /// the peak in about 125 000 steps.
  inline constexpr double keys_probe_width_2d  = 30;
  inline constexpr double keys_probe_width_3d  = 10;
  inline constexpr double keys_strain_per_step = 2e-8;
  /// Unbreakable keys' material: the UCS test ends at this axial strain
  /// (no peak; about 50 000 steps at keys_strain_per_step).
  inline constexpr double keys_elastic_strain_limit = 1e-3;

  /// Runs the probe for the region of `s` (which holds the material of
  /// `material_file`, or, without one, the `DEM region` keys' material,
  /// whose E, nu are then compared with the continuum's and whose UCS is
  /// reported) on `seeds` packings (region seed, +1, ...), prints the
  /// comparison table to `out` and writes probe.json into `json_dir` (when
  /// not empty). Returns true when every judged row passes: E, nu within
  /// probe_elastic_tolerance, UCS and BTS of the probe's seed mean and the
  /// file's within two standard errors of their difference (both seed
  /// scatters; with >= 2 probe seeds, one seed: not judged), every
  /// Brazilian disk split, and the continuum's E, nu the file's exactly.
  bool run_probe(const coupling::TunnelParams &s, const std::string &material_file,
                 int seeds, const std::string &json_dir, std::ostream &out);
} // namespace demfem::apps
