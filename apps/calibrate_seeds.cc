// `demfem calibrate` over several packing seeds (Problem/seeds; apps/calibrate.h):
// a material's properties are the means over packings, not one packing's
// values (docs/calibrate.md, "Several packings").
#include "apps/calibrate.h"
#include "common/statistics.h"
#include "dem/io/vtk_output.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

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
  } // namespace

  template <int dim>
  CalibrateOutcome run_calibration_seeds(const CalibrateSettings &s)
  {
    if (s.seeds <= 1)
      return run_calibration<dim>(s);
    CalibrateOutcome  outcome;
    std::vector<json> files;
    json              seeds = json::array();
    for (int k = 0; k < s.seeds; ++k)
      {
        CalibrateSettings one = s;
        one.mat.seed          = s.mat.seed + k;
        one.out               = s.out + "/seed_" + std::to_string(one.mat.seed);
        std::cerr << "demfem calibrate: packing " << k + 1 << " of " << s.seeds
                  << " (seed " << one.mat.seed << ") into " << one.out << std::endl;
        const CalibrateOutcome o = run_calibration<dim>(one);
        if (o.exit_code != 0 && outcome.exit_code == 0)
          outcome = o;
        files.push_back(read_json(one.out + "/material.json"));
        seeds.push_back(one.mat.seed);
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
    out["seeds"]            = seeds;
    out["seed_scatter"]     = scatter;
    out["seed_values"]      = values;
    out["seed_means"] =
        "every measured property is the mean over the packings of 'seeds' "
        "(nulls left out); seed_scatter: sample standard deviations; "
        "per-seed results in seed_<n>/";
    dem::vtkout::write_text_atomically(s.out + "/material.json", out.dump(2) + "\n");
    std::cerr << "demfem calibrate: wrote " << s.out << "/material.json (means over "
              << s.seeds << " packings)" << std::endl;
    return outcome;
  }

  template CalibrateOutcome run_calibration_seeds<2>(const CalibrateSettings &);
  template CalibrateOutcome run_calibration_seeds<3>(const CalibrateSettings &);
} // namespace demfem::apps
