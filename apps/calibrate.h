#pragma once
// Settings shared by the parts of `demfem calibrate` (calibrate_command.cc
// reads and validates them; calibrate_run.cc runs the genesis and the tests).
#include "dem/lab_tests.h"

#include <string>
#include <vector>

namespace demfem::apps
{
  /// A test of Tests/tests and what it runs.
  struct TestSpec
  {
    std::string          name;
    dem::TestKind        kind;
    dem::CompressionType ctype;
  };

  struct CalibrateSettings
  {
    int                   dim = 2;
    std::string           out, where;
    bool                  vtk = true;
    dem::MaterialParams   mat;
    dem::VesselParams     vessel;
    double                n_grains = 0;
    std::vector<TestSpec> tests;
    dem::LabTestParams    lab;
    bool                  rate_check = false;
  };

  /// Runs the calibration (creates the output directory); returns the exit code.
  template <int dim>
  int run_calibration(const CalibrateSettings &s);
} // namespace demfem::apps
