// `demfem calibrate` over several packing seeds (Problem/seeds; apps/calibrate.h):
// a material's properties are the means over packings, not one packing's
// values (docs/calibrate.md, "Several packings").
#include "apps/calibrate.h"
#include "apps/calibrate_output.h"
#include "apps/parallel_packings.h"
#include "common/statistics.h"
#include "dem/io/vtk_output.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

namespace demfem::apps
{
  namespace
  {
    using json = nlohmann::json;

    json read_json(const std::string &file)
    {
      std::ifstream in(file);
      return json::parse(in);
    }

    // Mean, sample standard deviation and the single values of `key` over
    // the seeds' objects; a null (not measured, e.g. the BTS of a disk that
    // did not split) is left out of the mean and kept as null in the values.
    void average(const std::vector<const json *> &objs, const std::string &key,
                 json &mean_into, json &sd_into, json &values_into)
    {
      std::vector<double> measured;
      json                values = json::array();
      for (const json *o : objs)
        {
          const auto it = o->find(key);
          if (it != o->end() && it->is_number())
            {
              measured.push_back(it->get<double>());
              values.push_back(measured.back());
            }
          else
            values.push_back(nullptr);
        }
      values_into[key] = values;
      if (measured.empty())
        {
          mean_into[key] = nullptr;
          sd_into[key]   = nullptr;
          return;
        }
      const auto i   = statistics::mean_interval(measured);
      mean_into[key] = i.mean;
      sd_into[key]   = measured.size() > 1 ? json(i.sd) : json(nullptr);
    }
    // The envelope of a triaxial series over the packings: each confining
    // pressure's peak averaged over the seeds and both envelopes fitted to
    // these means, so that the file's envelope, like every other number in
    // it, is the material's and not the first packing's. Each packing's own
    // fit (m_i, sigma_ci, c, phi) goes to seed_values with its scatter.
    void average_envelope(const std::vector<json> &files, int dim, const std::string &dir,
                          const std::string &where, json &out, json &scatter,
                          json &values)
    {
      std::vector<std::vector<double>> peaks;
      for (const auto &f : files)
        {
          const auto it = f.find("envelope");
          if (it == f.end() || !it->is_object())
            return; // no triaxial series in this run
          peaks.push_back((*it)["peak_axial_stresses_Pa"].get<std::vector<double>>());
        }
      StrengthEnvelope mean;
      mean.sigma_3 = files.front()["envelope"]["confining_pressures_Pa"]
                         .get<std::vector<double>>(); // the same list in every seed
      std::vector<double> sd;
      for (std::size_t k = 0; k < mean.sigma_3.size(); ++k)
        {
          std::vector<double> at;
          for (const auto &p : peaks)
            at.push_back(p.at(k));
          const auto i = statistics::mean_interval(at);
          mean.sigma_1.push_back(i.mean);
          sd.push_back(i.sd);
        }
      mean.fit(where);
      json e                         = mean.json().value();
      e["peak_axial_stresses_sd_Pa"] = sd;
      e["fitted_to"] = "the seed means of the peaks at each confining pressure";

      const std::vector<std::pair<const char *, std::vector<const char *>>> fits = {
          {"mi", {"hoek_brown", "mi"}},
          {"sigma_ci_Pa", {"hoek_brown", "sigma_ci_Pa"}},
          {"cohesion_Pa", {"mohr_coulomb", "cohesion_Pa"}},
          {"friction_angle_deg", {"mohr_coulomb", "friction_angle_deg"}}};
      std::vector<json> own; // each packing's fit, flattened
      for (const auto &f : files)
        {
          json o = json::object();
          for (const auto &[key, path] : fits)
            o[key] = f["envelope"][path[0]][path[1]];
          own.push_back(o);
        }
      std::vector<const json *> objs;
      for (const auto &o : own)
        objs.push_back(&o);
      json m = json::object(), es = json::object(), ev = json::object();
      for (const auto &[key, path] : fits)
        average(objs, key, m, es, ev);
      ev["peak_axial_stresses_Pa"]       = peaks;
      e["seed_mean_of_each_packing_fit"] = m;
      out["envelope"]                    = e;
      scatter["envelope"]                = es;
      values["envelope"]                 = ev;

      std::vector<PlotSeries> each;
      for (std::size_t k = 0; k < peaks.size(); ++k)
        {
          PlotSeries p{k == 0 ? "each packing" : "", {}, {}, "#999", true};
          for (std::size_t i = 0; i < peaks[k].size(); ++i)
            p.x.push_back(mean.sigma_3[i] / 1e6), p.y.push_back(peaks[k][i] / 1e6);
          each.push_back(p);
        }
      dem::vtkout::write_text_atomically(dir + "/envelope.svg", mean.svg(dim, each));
      std::cerr
          << "demfem calibrate: envelope of the seed-mean peaks: Hoek-Brown sigma_ci "
          << mean.hb.sigma_ci / 1e6 << " MPa, m_i " << mean.hb.mi
          << " (each packing's m_i: mean " << m["mi"] << ", sd " << es["mi"] << ")\n";
    }

    // The loading-rate check on the seed means (docs/calibrate.md, "Loading
    // rate and time step"): the peak of one brittle packing is chaotic, so
    // each test's peaks at the full and at the reduced rates are compared
    // over all packings as paired samples (statistics::paired_change).
    json rate_check_on_means(const std::vector<json> &summaries, int levels)
    {
      // Each test's per-seed result objects, by name (a triaxial series:
      // one per confining pressure).
      std::map<std::string, std::vector<const json *>> tests;
      for (const auto &s : summaries)
        for (const auto &[name, t] : s.at("tests").items())
          if (t.contains("tests") && t["tests"].is_array())
            for (const auto &point : t["tests"])
              tests[name + " " +
                    std::to_string(int(std::lround(point.value("Pc_Pa", 0.0) / 1e6))) +
                    " MPa"]
                  .push_back(&point);
          else
            tests[name].push_back(&t);
      json out = json::object();
      for (const auto &[name, objs] : tests)
        {
          if (objs.size() != summaries.size())
            continue;
          json entry = json::object();
          for (int level = 1; level <= levels; ++level)
            {
              const std::string   which = level == 1 ? "half" : "quarter";
              std::vector<double> full, reduced;
              for (const json *o : objs)
                if (o->contains("peak_Pa") && o->contains("peak_" + which + "_rate_Pa"))
                  {
                    full.push_back((*o)["peak_Pa"].get<double>());
                    reduced.push_back((*o)["peak_" + which + "_rate_Pa"].get<double>());
                  }
              if (full.size() != objs.size())
                continue;
              const auto c =
                  statistics::paired_change(full, reduced, calibrate_rate_tolerance);
              entry[which + "_rate"] = {{"relative_change_of_the_mean", c.change},
                                        {"standard_error", std::isfinite(c.standard_error)
                                                               ? json(c.standard_error)
                                                               : json(nullptr)},
                                        {"critical_t", std::isfinite(c.critical)
                                                           ? json(c.critical)
                                                           : json(nullptr)},
                                        {"packings", c.n},
                                        {"verdict", c.verdict}};
              std::cerr << "demfem calibrate: " << name << " at " << which
                        << " rate, on the seed means: " << 100 * c.change << " % +- "
                        << 100 * c.standard_error << " % (standard error, " << c.n
                        << " packings, t " << c.critical << "): " << c.verdict << "\n";
            }
          if (!entry.empty())
            out[name] = entry;
        }
      return out;
    }
    // How well the seed means are known (docs/calibrate.md, "Several
    // packings"): for each headline property its 95 % interval (Student t,
    // n - 1 degrees of freedom), relative to the mean, and the packings a
    // 5 % standard error of the mean would need, n_5 = (CoV / 0.05)^2: the
    // 1 000-grain 2D packings scatter by +-21 % in UCS, so a three-packing
    // mean is known to about +-12 % (one standard error), not 5 %.
    json seed_confidence(const json &values, std::size_t packings)
    {
      json out = json::object();
      std::cerr << "demfem calibrate: seed means over " << packings
                << " packings, 95 % interval and packings for a 5 % standard error:\n";
      for (const char *key : {"E", "nu", "ucs", "bts", "direct_tension",
                              "crack_initiation", "crack_damage"})
        {
          const auto it = values.find(key);
          if (it == values.end())
            continue;
          std::vector<double> measured;
          for (const auto &v : *it)
            if (v.is_number())
              measured.push_back(v.get<double>());
          const auto i = statistics::mean_interval(measured);
          if (i.n < 2 || !(std::abs(i.mean) > 0))
            continue;
          const double cov = i.sd / std::abs(i.mean);
          const auto   n5  = std::max<std::size_t>(
              1, static_cast<std::size_t>(std::ceil(cov * cov / (0.05 * 0.05))));
          out[key] = {{"mean", i.mean},
                      {"half_width_95", i.half_width},
                      {"relative_half_width_95", i.half_width / std::abs(i.mean)},
                      {"packings", i.n},
                      {"packings_for_5_percent_standard_error", n5}};
          std::cerr << "  " << key << " " << i.mean << " +- "
                    << 100 * i.half_width / std::abs(i.mean) << " % (" << i.n
                    << " packings; sd " << 100 * cov << " %; " << n5
                    << " packings for a 5 % standard error)\n";
        }
      return out;
    }
  } // namespace

  template <int dim>
  CalibrateOutcome run_calibration_seeds(const CalibrateSettings &s)
  {
    if (s.seeds <= 1)
      return run_calibration<dim>(s);
    // The packings side by side, one OpenMP thread each
    // (apps/parallel_packings.h); their files are read in seed order.
    const int at_a_time = packings_at_a_time(s.seeds);
    if (at_a_time > 1)
      std::cerr << "demfem calibrate: " << s.seeds << " packings, " << at_a_time
                << " at a time (one thread each)" << std::endl;
    std::vector<CalibrateOutcome>  outcomes(s.seeds);
    std::vector<CalibrateSettings> runs(s.seeds, s);
    for_each_packing(s.seeds, [&](const int k) {
      CalibrateSettings &one = runs[k];
      one.mat.seed           = s.mat.seed + k;
      one.out                = s.out + "/seed_" + std::to_string(one.mat.seed);
      one.log_tag            = "seed " + std::to_string(one.mat.seed) + ": ";
      std::cerr << "demfem calibrate: packing " << k + 1 << " of " << s.seeds << " (seed "
                << one.mat.seed << ") into " << one.out << std::endl;
      outcomes[k] = run_calibration<dim>(one);
    });
    CalibrateOutcome  outcome;
    std::vector<json> files, summaries;
    json              seeds = json::array();
    for (int k = 0; k < s.seeds; ++k)
      {
        if (outcomes[k].exit_code != 0 && outcome.exit_code == 0)
          outcome = outcomes[k];
        files.push_back(read_json(runs[k].out + "/material.json"));
        summaries.push_back(read_json(runs[k].out + "/summary.json"));
        seeds.push_back(runs[k].mat.seed);
      }

    // The first seed's file (microparameters, lab_tests, units, texts) with
    // every measured number replaced by the seed mean.
    json                      out     = files.front();
    json                      scatter = json::object(), values = json::object();
    std::vector<const json *> objs, ratios;
    for (const auto &f : files)
      {
        objs.push_back(&f);
        if (const auto it = f.find("ratios"); it != f.end() && it->is_object())
          ratios.push_back(&*it);
      }
    for (const auto &[key, v] : files.front().items())
      if ((v.is_number() || v.is_null()) && key != "dim" && key != "confining_pressure")
        average(objs, key, out, scatter, values);
    if (ratios.size() == files.size())
      {
        json rs = json::object(), rv = json::object();
        for (const auto &[key, v] : files.front()["ratios"].items())
          if (v.is_number() || v.is_null())
            average(ratios, key, out["ratios"], rs, rv);
        scatter["ratios"] = rs;
        values["ratios"]  = rv;
      }
    // Failure modes of each seed's Brazilian disk (a mean of "split" is
    // not a thing).
    json modes = json::array();
    for (const auto &f : files)
      modes.push_back(f.value("bts_failure_mode", std::string("not run")));
    values["bts_failure_mode"] = modes;
    std::size_t split          = 0;
    for (const auto &m : modes)
      split += m == "split";
    out["bts_failure_mode"] = split == files.size() ? "split"
                              : split == 0          ? files.front()["bts_failure_mode"]
                                           : json("split in " + std::to_string(split) +
                                                  " of " + std::to_string(files.size()));
    average_envelope(files, dim, s.out, s.where, out, scatter, values);
    if (s.rate_check > 0)
      out["rate_check_on_seed_means"] = rate_check_on_means(summaries, s.rate_check);
    out["seeds"]           = seeds;
    out["seed_scatter"]    = scatter;
    out["seed_values"]     = values;
    out["seed_confidence"] = seed_confidence(values, files.size());
    out["seed_means"] =
        "every measured property is the mean over the packings of 'seeds' "
        "(nulls left out); seed_scatter: sample standard deviations; "
        "seed_confidence: 95 % intervals of the headline means and the "
        "packings a 5 % standard error needs; per-seed results in seed_<n>/";
    dem::vtkout::write_text_atomically(s.out + "/material.json", out.dump(2) + "\n");
    std::cerr << "demfem calibrate: wrote " << s.out << "/material.json (means over "
              << s.seeds << " packings)" << std::endl;
    return outcome;
  }

  template CalibrateOutcome run_calibration_seeds<2>(const CalibrateSettings &);
  template CalibrateOutcome run_calibration_seeds<3>(const CalibrateSettings &);
} // namespace demfem::apps
