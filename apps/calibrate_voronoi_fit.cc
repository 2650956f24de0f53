// `demfem calibrate FILE.prm --fit` for Voronoi grains (calibrate_voronoi.h;
// docs/calibrate.md, "Automatic calibration"): the searched names of a
// Voronoi material and the measurement of a parameter set on the tests of
// dem/voronoi/voronoi_lab_test.h; the staged search is
// apps/calibrate_fit_search.cc, as for the bonded-particle materials.
#include "apps/calibrate_fit.h"
#include "apps/calibrate_voronoi.h"
#include "dem/specimen/envelope.h"

#include <iostream>
#include <map>
#include <stdexcept>

namespace demfem::apps
{
  namespace
  {
    namespace vor = dem::voronoi;

    bool is_elastic_parameter(const std::string &name)
    {
      return name == "contact modulus" || name == "stiffness ratio" ||
             name == "grain youngs modulus" || name == "grain poisson ratio";
    }

    // One evaluation: `seeds` packings of the material `s`, each measured by
    // the tests the targets need (elastic: a UCS test stopped at a small
    // strain). A packing whose contacts refuse the material (a fracture
    // energy below a contact's brittle value) or a test ended at its step
    // limit fails the evaluation.
    FitMeasurement measure(const VoronoiCalibrateSettings &s,
                           const std::vector<std::string> &targets, bool elastic)
    {
      std::map<std::string, std::vector<double>> values;
      std::string                                error;
      try
        {
          VoronoiCalibrateSettings m = s;
          m.tests.clear();
          m.tests.push_back({"ucs", vor::VoronoiTest::unconfined_compression, 0});
          if (elastic)
            m.lab.strain_limit = s.fit.elastic_strain;
          else
            {
              if (fit_needs(targets, "brazilian"))
                m.tests.push_back({"brazilian", vor::VoronoiTest::brazilian, 0});
              if (fit_needs(targets, "direct tension"))
                m.tests.push_back(
                    {"direct tension", vor::VoronoiTest::direct_tension, 0});
              if (fit_needs(targets, "triaxial series"))
                for (const auto &t : s.tests)
                  if (t.in_series)
                    m.tests.push_back(t);
            }
          for (int k = 0; k < s.fit.seeds; ++k)
            {
              m.specimen.seed                 = s.specimen.seed + std::uint64_t(k);
              const VoronoiSpecimens specimen = make_voronoi_specimens(m);
              std::vector<double>    s3, s1;
              for (const auto &t : m.tests)
                {
                  const auto r = run_voronoi_test(m, specimen, t);
                  if (r.status == vor::VoronoiLabStatus::step_limit_reached)
                    throw std::runtime_error(t.label +
                                             " test ended at Tests/step limit before "
                                             "its peak was certain");
                  if (t.in_series)
                    s3.push_back(t.confining_pressure), s1.push_back(r.peak_stress);
                  else if (t.label == "ucs")
                    {
                      const auto el = plane_strain_constants(r.E, r.nu);
                      values["E"].push_back(el.E);
                      values["nu"].push_back(el.nu);
                      if (!elastic)
                        {
                          values["ucs"].push_back(r.peak_stress);
                          values["crack initiation ratio"].push_back(
                              voronoi_crack_initiation(r, s, s.crack_initiation_method,
                                                       true) /
                              r.peak_stress);
                        }
                    }
                  else if (t.label == "brazilian")
                    values["bts"].push_back(r.peak_stress);
                  else
                    values["direct tension"].push_back(r.peak_stress);
                }
              if (!s3.empty())
                values["mi"].push_back(dem::fit_hoek_brown(s3, s1, "fit").mi);
            }
        }
      catch (const std::exception &e)
        {
          error = e.what();
        }
      return summarize_seeds(values, error);
    }
  } // namespace

  double &voronoi_fit_parameter(VoronoiCalibrateSettings &s, const std::string &name,
                                const std::string &where)
  {
    auto &c = s.contact;
    if (name == "contact modulus")
      return c.contact_modulus;
    if (name == "stiffness ratio")
      return c.kratio;
    if (name == "tensile strength")
      return c.tensile_strength;
    if (name == "cohesion")
      return c.cohesion;
    if (name == "friction")
      return c.friction;
    if (name == "tensile fracture energy")
      return c.tensile_fracture_energy;
    if (name == "shear fracture energy")
      return c.shear_fracture_energy;
    if (s.flexible && name == "grain youngs modulus")
      return s.grain.youngs_modulus;
    if (s.flexible && name == "grain poisson ratio")
      return s.grain.poisson_ratio;
    throw std::invalid_argument(
        where + ": Fit/parameters: '" + name + "' is not a searchable parameter of a " +
        (s.flexible ? "flexible-voronoi" : "rigid-voronoi") +
        " material (allowed, the keys of Material/Voronoi: contact modulus, stiffness "
        "ratio, tensile strength, cohesion, friction, tensile fracture energy, shear "
        "fracture energy" +
        (s.flexible ? ", grain youngs modulus, grain poisson ratio)" : ")"));
  }

  CalibrateOutcome run_voronoi_fit(const VoronoiCalibrateSettings &s)
  {
    auto with_values = [&](const std::vector<double> &values) {
      VoronoiCalibrateSettings m = s;
      for (std::size_t i = 0; i < values.size(); ++i)
        voronoi_fit_parameter(m, s.fit.parameters[i].name, "fit") = values[i];
      // The flexible grains' elasticity shares the contacts' thickness and
      // the grain density (as read_voronoi_settings sets them).
      m.grain.density   = m.density;
      m.grain.thickness = m.contact.thickness;
      return m;
    };
    FitProblem problem;
    for (const auto &p : s.fit.parameters)
      {
        VoronoiCalibrateSettings probe = s;
        problem.initial.push_back(voronoi_fit_parameter(probe, p.name, "fit"));
      }
    problem.is_elastic_parameter = is_elastic_parameter;
    problem.measure              = [&](const std::vector<double>      &values,
                          const std::vector<std::string> &targets, bool elastic) {
      return measure(with_values(values), targets, elastic);
    };
    const FitSearchResult fit = run_fit_search(s.fit, problem, s.out);

    // material.json and the test outputs of the best material.
    const VoronoiCalibrateSettings best = with_values(fit.best);
    const CalibrateOutcome         rc =
        run_voronoi_calibration(best, make_voronoi_specimens(best));
    if (rc.exit_code != 0)
      return rc;
    return fit_outcome(fit);
  }
} // namespace demfem::apps
