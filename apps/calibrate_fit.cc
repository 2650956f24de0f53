// `demfem calibrate FILE.prm --fit` for the bonded-particle materials
// (docs/calibrate.md, "Automatic calibration"): the searched names of a
// dem::MaterialParams and the measurement of a parameter set on the lab
// tests of dem/specimen/lab_tests.h; the staged search is
// apps/calibrate_fit_search.cc.
#include "apps/calibrate_fit.h"
#include "apps/calibrate.h"
#include "apps/lab_progress.h"
#include "apps/parallel_packings.h"
#include "dem/io/checkpoint.h"
#include "dem/specimen/envelope.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

namespace demfem::apps
{
  namespace
  {
    namespace fs = std::filesystem;

    bool is_elastic_parameter(const std::string &name)
    {
      return name == "effective modulus" || name == "stiffness ratio" ||
             name == "linear effective modulus" || name == "linear stiffness ratio" ||
             name == "bond effective modulus" || name == "bond stiffness ratio";
    }

    // The settings of the elastic stage's small-strain UCS test. With the
    // modulus window a fraction of the test's peak (Tests/fit window
    // low/high), a test stopped at Fit/elastic strain measures E and nu at
    // 5-20 % of its own end load, 1-4 MPa on the 2D example, where the
    // seated specimen is stiffer and nu lower than in the full test's
    // window at 5-20 % of its UCS (the example's six packings at kappa*
    // 3.7: E 72.4 GPa, nu 0.226 at E* 107.5 GPa against the full tests'
    // 68.2 GPa, 0.264 at E* 106 GPa), so the elastic stage drove kappa* to
    // its bound for a nu the full test then missed. With a
    // UCS target, the elastic test measures in the stress window the full
    // test will use at that UCS (Tests/fit window stress low/high) and runs
    // until its platen strain is 1.5 times the window's top over the E
    // target: the platen strain exceeds the specimen's by the grain-platen
    // compliance (the 2D example: E from the platens 10-20 % below E).
    dem::LabTestParams elastic_test_settings(const CalibrateSettings &s)
    {
      dem::LabTestParams lp = s.lab;
      lp.kind               = dem::TestKind::compression;
      lp.ctype              = dem::CompressionType::unconfined;
      lp.Pc                 = 0;
      lp.strain_limit       = s.fit.elastic_strain;
      const FitTarget *ucs = nullptr, *E = nullptr;
      for (const auto &t : s.fit.targets)
        {
          if (t.name == "ucs")
            ucs = &t;
          if (t.name == "E")
            E = &t;
        }
      if (lp.fit_stress_hi > 0 || !ucs)
        return lp;
      lp.fit_window_at(ucs->value);
      if (E)
        lp.strain_limit = std::max(lp.strain_limit, 1.5 * lp.fit_stress_hi / E->value);
      return lp;
    }

    // One packing's measurements in an evaluation, and what was left out.
    struct PackingValues
    {
      std::map<std::string, std::vector<double>> values;
      std::string                                note;
    };

    // One evaluation: Fit/seeds packings of `mat`, each measured by the
    // tests the targets need (elastic: a UCS test stopped at a small
    // strain), and the BTS over Fit/brazilian seeds disks, those beyond
    // Fit/seeds tested in the Brazilian test only. The packings run side by
    // side (apps/parallel_packings.h), each with its own scratch checkpoint
    // `scratch_stem`_k.h5; their values are gathered in seed order, so the
    // means are those of a sequential run bit for bit.
    template <int dim>
    FitMeasurement measure(const CalibrateSettings &s, const dem::MaterialParams &mat,
                           const std::vector<std::string> &targets, bool elastic,
                           const std::string &scratch_stem)
    {
      const int n_full = s.fit.seeds;
      const int n_disks =
          !elastic && fit_needs(targets, "brazilian") ? s.fit.brazilian_disks() : 0;
      const int                  n_packings = std::max(n_full, n_disks);
      std::vector<PackingValues> packings(n_packings);
      std::string                error;
      const dem::LabTestParams   elastic_lab = elastic_test_settings(s);
      try
        {
          for_each_packing(n_packings, [&](const int k) {
            const bool        full    = k < n_full;  // every test the targets need
            const bool        disk    = k < n_disks; // the Brazilian test
            auto             &values  = packings[k].values;
            auto             &note    = packings[k].note;
            const std::string scratch = scratch_stem + "_" + std::to_string(k) + ".h5";
            // The scratch files go whatever happens to this packing.
            struct Remove
            {
              std::string f;
              ~Remove()
              {
                std::error_code ignored; // a destructor must not throw
                fs::remove(f, ignored);
                fs::remove(f + ".prev", ignored);
              }
            } remove_scratch{scratch};
            dem::MaterialParams m = mat;
            m.seed                = mat.seed + std::uint64_t(k);
            // The box specimen, unless this packing only tests a Brazilian
            // disk packed on its own.
            std::unique_ptr<dem::Specimen<dim>> first;
            if (full || !dem::own_brazilian_specimen(s.lab))
              {
                first = std::make_unique<dem::Specimen<dim>>(
                    dem::build_specimen<dim>(m, s.vessel, nullptr, s.where));
                dem::write_checkpoint(first->model, scratch, {});
              }
            auto finished = [](dem::LabTestResult r) {
              if (r.ended_by == "step limit")
                throw std::runtime_error(std::string(dem::test_kind_name(r.kind)) +
                                         " test ended at Tests/step limit before its "
                                         "peak was certain");
              return r;
            };
            // Each test prints its progress line (phase, stress, cracks,
            // ETA; apps/lab_progress.h), into a log file too: an
            // evaluation takes minutes in 2D and more in 3D.
            auto with_progress = [&](dem::Specimen<dim>       &sp,
                                     const dem::LabTestParams &lp) {
              std::ostringstream label;
              label << "fit, seed " << m.seed << ", " << dem::test_kind_name(lp.kind);
              // Tests/confining pressure applies to confined compression
              // only; the Brazilian and direct tension tests ignore it.
              if (lp.kind == dem::TestKind::compression &&
                  lp.ctype != dem::CompressionType::unconfined && lp.Pc > 0)
                label << " at " << lp.Pc / 1e6 << " MPa";
              return finished(run_lab_test_with_progress(sp, lp, label.str()));
            };
            auto run_with = [&](const dem::LabTestParams &lp) {
              auto sp = clone_specimen(*first, scratch);
              return with_progress(*sp, lp);
            };
            auto run = [&](dem::TestKind kind, dem::CompressionType ctype, double Pc) {
              dem::LabTestParams lp = s.lab;
              lp.kind = kind, lp.ctype = ctype, lp.Pc = Pc;
              return run_with(lp);
            };
            using dem::CompressionType, dem::TestKind;
            if (full && (elastic || fit_needs(targets, "ucs")))
              {
                const auto r =
                    elastic ? run_with(elastic_lab)
                            : run(TestKind::compression, CompressionType::unconfined, 0);
                values["E"].push_back(r.E);
                values["nu"].push_back(r.nu);
                if (!elastic)
                  {
                    values["ucs"].push_back(r.peak);
                    values["crack initiation ratio"].push_back(r.crack_initiation /
                                                               r.peak);
                  }
              }
            if (elastic)
              return;
            if (disk)
              {
                // A disk that did not split along its loaded diameter has
                // a peak that is no tensile strength (ISRM 1978;
                // dem/specimen/brazilian_failure.h): that packing is left
                // out of the BTS mean and named in fit.csv, rather than
                // pulling the mean up by a crushing load (docs/calibrate.md).
                dem::LabTestResult r;
                if (dem::own_brazilian_specimen(s.lab))
                  {
                    // Its own specimen (Tests/brazilian diameter), packed
                    // for this evaluation at the same grain size and seed.
                    auto sp = dem::build_specimen<dim>(
                        m, dem::brazilian_vessel(s.vessel, s.lab, dim), nullptr, s.where);
                    dem::LabTestParams lp = s.lab;
                    lp.kind               = TestKind::brazilian;
                    r                     = with_progress(sp, lp);
                  }
                else
                  r = run(TestKind::brazilian, CompressionType::unconfined, 0);
                if (r.failure_mode == "split")
                  values["bts"].push_back(r.peak);
                else
                  {
                    std::ostringstream o;
                    o.precision(3);
                    o << (note.empty() ? "" : "; ") << "seed " << m.seed << " Brazilian "
                      << r.failure_mode << " (split fraction " << r.split_fraction
                      << ", peak " << r.peak / 1e6 << " MPa) left out of the bts mean";
                    note += o.str();
                  }
              }
            if (full && fit_needs(targets, "direct tension"))
              values["direct tension"].push_back(
                  run(TestKind::direct_tension, CompressionType::unconfined, 0).peak);
            if (full && fit_needs(targets, "triaxial series"))
              {
                std::vector<double> s1;
                for (double Pc : s.confining_pressures)
                  s1.push_back(run(TestKind::compression,
                                   Pc > 0 ? CompressionType::confined
                                          : CompressionType::unconfined,
                                   Pc)
                                   .peak);
                values["mi"].push_back(
                    dem::fit_hoek_brown(s.confining_pressures, s1, "fit").mi);
              }
          });
        }
      catch (const std::exception &e)
        {
          error = e.what();
        }
      std::map<std::string, std::vector<double>> values;
      std::string                                note;
      for (const auto &p : packings)
        {
          for (const auto &[key, v] : p.values)
            values[key].insert(values[key].end(), v.begin(), v.end());
          if (!p.note.empty())
            note += (note.empty() ? "" : "; ") + p.note;
        }
      // No packing split: the material has no measured BTS, the evaluation
      // fails (logged with the note) rather than scoring a missing target.
      if (error.empty() && !elastic && fit_needs(targets, "brazilian") &&
          values.count("bts") == 0)
        error = "no Brazilian disk split along its loaded diameter: " + note;
      FitMeasurement out = summarize_seeds(values, error);
      out.note           = note;
      return out;
    }
  } // namespace

  double &fit_parameter(dem::MaterialParams &m, const std::string &name,
                        const std::string &where)
  {
    if (name == "effective modulus")
      return m.emod;
    if (name == "stiffness ratio")
      return m.krat;
    if (name == "linear effective modulus")
      return m.lnm_emod;
    if (name == "linear stiffness ratio")
      return m.lnm_krat;
    if (name == "friction")
      return m.fric;
    if (name == "installation gap")
      return m.igap;
    if (m.type == "flatjointed")
      {
        if (name == "tensile strength mean")
          return m.fj_ten.mean;
        if (name == "tensile strength sd")
          return m.fj_ten.sd;
        if (name == "tensile strength min")
          return m.fj_ten.min;
        if (name == "cohesion mean")
          return m.fj_coh.mean;
        if (name == "cohesion sd")
          return m.fj_coh.sd;
        if (name == "friction angle")
          return m.fj_fa;
        if (name == "bonded fraction")
          return m.fj_B;
        if (name == "gapped fraction")
          return m.fj_G;
        if (name == "gap mean")
          return m.fj_gap.mean;
        if (name == "radius multiplier")
          return m.fj_rmul;
      }
    if (m.type == "parallelbonded")
      {
        if (name == "tensile strength mean")
          return m.pb_ten.mean;
        if (name == "tensile strength sd")
          return m.pb_ten.sd;
        if (name == "cohesion mean")
          return m.pb_coh.mean;
        if (name == "cohesion sd")
          return m.pb_coh.sd;
        if (name == "friction angle")
          return m.pb_fa;
        if (name == "bond effective modulus")
          return m.pb_bemod;
        if (name == "bond stiffness ratio")
          return m.pb_bkrat;
        if (name == "radius multiplier")
          return m.pb_rmul;
      }
    if (m.type == "contactbonded")
      {
        if (name == "tensile strength mean")
          return m.cb_tens.mean;
        if (name == "tensile strength sd")
          return m.cb_tens.sd;
        if (name == "shear strength mean")
          return m.cb_shears.mean;
        if (name == "shear strength sd")
          return m.cb_shears.sd;
      }
    throw std::invalid_argument(
        where + ": Fit/parameters: '" + name + "' is not a searchable parameter of a " +
        m.type +
        " material (allowed: effective modulus, stiffness ratio, linear effective "
        "modulus, "
        "linear stiffness ratio, friction, installation gap; flat joint and parallel "
        "bond: "
        "tensile strength mean|sd, cohesion mean|sd, friction angle, radius multiplier; "
        "flat "
        "joint: tensile strength min, bonded fraction, gapped fraction, gap mean; "
        "parallel bond: bond "
        "effective "
        "modulus, bond stiffness ratio; contact bond: tensile|shear strength mean|sd)");
  }

  template <int dim>
  CalibrateOutcome run_fit(const CalibrateSettings &s0)
  {
    CalibrateSettings s = s0;
    if (s.n_grains > 0)
      dem::set_grain_count<dim>(s.mat, s.vessel, s.n_grains);
    s.n_grains = 0; // the diameter multiplier now holds it for every evaluation
    fs::create_directories(s.out);
    const std::string scratch     = s.out + "/fit_specimen"; // _k.h5 per packing
    auto              with_values = [&](const std::vector<double> &values) {
      dem::MaterialParams m = s.mat;
      for (std::size_t i = 0; i < values.size(); ++i)
        fit_parameter(m, s.fit.parameters[i].name, "fit") = values[i];
      return m;
    };
    FitProblem problem;
    for (const auto &p : s.fit.parameters)
      problem.initial.push_back(fit_parameter(s.mat, p.name, "fit"));
    problem.is_elastic_parameter = is_elastic_parameter;
    problem.measure              = [&](const std::vector<double>      &values,
                          const std::vector<std::string> &targets, bool elastic) {
      return measure<dim>(s, with_values(values), targets, elastic, scratch);
    };
    if (const int k = packings_at_a_time(s.fit.seeds); k > 1)
      std::cerr << "demfem calibrate --fit: " << s.fit.seeds
                << " packings per evaluation, " << k << " at a time (one thread each)\n";
    if (const int n = s.fit.brazilian_disks(); n != s.fit.seeds)
      std::cerr << "demfem calibrate --fit: the bts over " << n
                << " Brazilian disks per evaluation (Fit/brazilian seeds), "
                << packings_at_a_time(std::max(n, s.fit.seeds)) << " at a time\n";
    const FitSearchResult fit = run_fit_search(s.fit, problem, s.out);

    // material.json and the test outputs of the best material, on
    // Problem/seeds packings as without --fit (with Problem/seeds =
    // Fit/seeds it is the seed mean of the packings the fit measured).
    CalibrateSettings final_s = s;
    final_s.mat               = with_values(fit.best);
    final_s.fit.enabled       = false;
    const CalibrateOutcome rc = run_calibration_seeds<dim>(final_s);
    if (rc.exit_code != 0)
      return rc;
    return fit_outcome(fit);
  }

  CalibrateOutcome fit_outcome(const FitSearchResult &fit)
  {
    if (fit.all_within)
      return {};
    std::cerr << "demfem calibrate --fit: the targets were not all reached within "
                 "the budget (fit.json: status targets_not_reached); the best material "
                 "found is in material.json\n";
    return {3, "targets_not_reached"};
  }

  template CalibrateOutcome run_fit<2>(const CalibrateSettings &);
  template CalibrateOutcome run_fit<3>(const CalibrateSettings &);
} // namespace demfem::apps
