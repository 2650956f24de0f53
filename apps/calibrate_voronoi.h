#pragma once
// `demfem calibrate` with Material/type = rigid-voronoi | flexible-voronoi:
// Voronoi (Laguerre) grains of dem/voronoi (docs/voronoi.md; seed 004 §2)
// in the laboratory tests of dem/voronoi/voronoi_lab_test.h, with the outputs
// of the bonded-particle material types (docs/calibrate.md, "Voronoi
// grains"). 2D only: the Voronoi grains are a 2D library.
#include <deal.II/base/parameter_handler.h>

#include "apps/calibrate.h"
#include "dem/voronoi/voronoi_lab_test.h"

#include <string>
#include <vector>

namespace demfem::apps
{
  /// One test of a Voronoi calibration.
  struct VoronoiTestSpec
  {
    std::string               label; ///< "ucs", "triaxial", "triaxial series 5 MPa", ...
    dem::voronoi::VoronoiTest test;
    double                    confining_pressure = 0;     ///< [Pa]
    bool                      in_series          = false; ///< one of the triaxial series
  };

  /// Everything a Voronoi calibration needs, each value checked where it was
  /// read (calibrate_voronoi_prm.cc).
  struct VoronoiCalibrateSettings
  {
    bool        flexible = false;
    std::string out, where;
    bool        vtk = true;
    /// The rectangular specimen (W x H, the vessel of Vessel/width, height).
    dem::voronoi::VoronoiSpecimenParams specimen;
    dem::voronoi::ContactMaterial       contact;
    double                              density = 2650; ///< grain density [kg/m^3]
    dem::voronoi::GrainElasticity       grain;          ///< flexible grains
    /// Shared test parameters (test kind and Pc are set per test).
    dem::voronoi::VoronoiLabParams lab;
    /// Brazilian platen friction (the compression platens are frictionless).
    double brazilian_platen_friction = 0.5;
    /// Crack initiation: the first history row whose crack count reaches
    /// this fraction of the count at the peak (docs/calibrate.md).
    double                       crack_initiation_fraction = 0.01;
    std::vector<VoronoiTestSpec> tests;
  };

  /// True for the Material/type values of Voronoi grains.
  bool is_voronoi_type(const std::string &type);

  /// The Material/type values of Voronoi grains, as a Patterns::Selection
  /// fragment ("rigid-voronoi|flexible-voronoi").
  const char *voronoi_type_names();

  /// Declares subsection Voronoi (called inside subsection Material).
  void declare_voronoi_parameters(dealii::ParameterHandler &prm);

  /// Reads and checks every key a Voronoi calibration uses (errors name the
  /// key, the file and the allowed range), refusing the keys and options
  /// the Voronoi grains do not have (3D, --fit, a joint, the loading-rate
  /// repeats, the uniaxial-strain test, the Brazilian test of flexible
  /// grains).
  VoronoiCalibrateSettings read_voronoi_settings(dealii::ParameterHandler &prm,
                                                 const std::string &where, bool fit);

  /// The packed and tessellated specimens of a Voronoi calibration: the
  /// rectangle of the compression and tension tests, the disk of the
  /// Brazilian test (if asked for).
  struct VoronoiSpecimens
  {
    dem::voronoi::VoronoiSpecimen rectangle, disk;
    bool                          has_disk  = false;
    double                        genesis_s = 0;
  };

  /// Packs and tessellates the specimens and checks the fracture energies
  /// against every contact's brittle value (they depend on the centre
  /// distances), so that a bad material is refused before the output
  /// directory is made.
  VoronoiSpecimens make_voronoi_specimens(const VoronoiCalibrateSettings &s);

  /// Runs the tests and writes material.json, summary.json, the histories
  /// and (rigid grains) the VTK files into s.out: step_limit_reached (exit
  /// 3) when a test ended at its step limit.
  CalibrateOutcome run_voronoi_calibration(const VoronoiCalibrateSettings &s,
                                           const VoronoiSpecimens         &specimens);
} // namespace demfem::apps
