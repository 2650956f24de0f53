#pragma once
// `demfem calibrate` with Material/type = rigid-voronoi | flexible-voronoi:
// Voronoi (Laguerre) grains of dem/voronoi (docs/voronoi.md; seed 004 §2)
// in the laboratory tests of dem/voronoi/voronoi_lab_test.h, with the outputs
// of the bonded-particle material types (docs/calibrate.md, "Voronoi
// grains"). 2D only: the Voronoi grains are a 2D library.
#include <deal.II/base/parameter_handler.h>

#include "apps/calibrate.h"
#include "apps/calibrate_fit.h"
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
    /// Crack initiation (docs/calibrate.md, as the bonded materials): the
    /// method material.json reports, the crack count's fraction of the
    /// count at the peak, the crack volumetric strain's threshold as a
    /// fraction of the elastic volumetric strain at the peak.
    dem::CrackInitiationMethod crack_initiation_method =
        dem::CrackInitiationMethod::volumetric_strain;
    double                       crack_initiation_fraction = 0.01;
    double                       crack_volumetric_fraction = 0.05;
    std::vector<VoronoiTestSpec> tests;
    FitSettings                  fit; ///< --fit (subsection Fit)
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
  /// the Voronoi grains do not have (3D, a joint, the loading-rate repeats,
  /// the uniaxial-strain test); with `fit`, subsection Fit too.
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

  /// One test of a calibration on its specimen (the disk for the
  /// Brazilian test): the test's kind, Pc and platen friction on the
  /// shared parameters s.lab. With a non-empty `vtk_base`, the model at the
  /// end is written to <vtk_base>{cells,points,cracks}.vtp (rigid: the
  /// cells; flexible: the element triangles).
  dem::voronoi::VoronoiLabResult run_voronoi_test(const VoronoiCalibrateSettings &s,
                                                  const VoronoiSpecimens         &sp,
                                                  const VoronoiTestSpec          &t,
                                                  const std::string &vtk_base = "");

  /// Crack-initiation stress (axial stress magnitude) of test `r` by
  /// method: crack count, when the count first reaches
  /// s.crack_initiation_fraction of the count at the peak row; crack
  /// volumetric strain or lateral strain response (compression tests only,
  /// dem/specimen/crack_initiation.h; the other tests report the crack
  /// count). As the bonded materials
  /// (docs/calibrate.md). NaN where the method finds none.
  double voronoi_crack_initiation(const dem::voronoi::VoronoiLabResult &r,
                                  const VoronoiCalibrateSettings       &s,
                                  dem::CrackInitiationMethod method, bool compression);

  /// The plane-strain pair for the continuum from the 2D constants E', nu'
  /// of the free-sided specimen (docs/architecture.md).
  struct PlaneStrainConstants
  {
    double E = 0, nu = 0;
  };
  PlaneStrainConstants plane_strain_constants(double E_2d, double nu_2d);

  /// The member of `s` a Fit/parameters name searches (contact modulus,
  /// stiffness ratio, tensile strength, cohesion, friction, tensile|shear
  /// fracture energy; flexible grains: grain youngs modulus, grain poisson
  /// ratio); std::invalid_argument naming `where` and the allowed names.
  double &voronoi_fit_parameter(VoronoiCalibrateSettings &s, const std::string &name,
                                const std::string &where);

  /// `demfem calibrate --fit` for Voronoi grains (calibrate_voronoi_fit.cc):
  /// the staged search (apps/calibrate_fit.h) with `Fit/seeds` packings per
  /// evaluation, then the calibration of the best material into s.out.
  CalibrateOutcome run_voronoi_fit(const VoronoiCalibrateSettings &s);
} // namespace demfem::apps
