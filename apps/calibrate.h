#pragma once
// Settings shared by the parts of `demfem calibrate` (calibrate_command.cc
// reads and validates them; calibrate_run.cc runs the genesis and the tests).
#include "dem/lab_tests.h"
#include "dem/smooth_joint_law.h"
#include <array>

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
    /// Slower repeats of each test (fistPkg §5.4): 0 none, 1 at half rate,
    /// 2 at half and at quarter rate.
    int rate_check = 0;
    /// Tests/confining pressures: one test each in the triaxial series [Pa].
    std::vector<double> confining_pressures;
    /// Smooth-jointed interface (fistPkg §2.8): plane through joint_point
    /// with the orientation and properties of joint_sj (3D uses all three
    /// coordinates, 2D the first two).
    bool                           joint = false;
    std::array<double, 3>          joint_point{{0, 0, 0}};
    dem::SmoothJointLaw<3>::Params joint_sj;
  };

  /// Runs the calibration (creates the output directory); returns the exit code.
  template <int dim>
  int run_calibration(const CalibrateSettings &s);
} // namespace demfem::apps
