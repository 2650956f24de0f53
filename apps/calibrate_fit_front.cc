// Which targets of a fit conflict (docs/calibrate.md, "Which targets
// conflict"): the evaluations of a fit.csv, read by their column names, are
// analysed pair by pair (dem/specimen/target_front.h) into fit_front.csv,
// fit_front.json and fit_front.svg. Written at the end of every `--fit`, and
// by `demfem calibrate FILE.prm --front FIT.csv` for an earlier fit's log.
#include "apps/calibrate_fit.h"
#include "apps/calibrate_output.h"
#include "dem/io/vtk_output.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace demfem::apps
{
  namespace
  {
    const FitTarget &target_named(const std::vector<FitTarget> &targets,
                                  const std::string            &name)
    {
      return *std::find_if(targets.begin(), targets.end(),
                           [&](const FitTarget &t) { return t.name == name; });
    }

    // The pair's evaluations as signed relative errors [%]: all of them, the
    // front, and the tolerance box.
    std::string pair_svg(const dem::TargetPairFront               &p,
                         const std::vector<FitTarget>             &targets,
                         const std::vector<dem::TargetEvaluation> &evaluations)
    {
      PlotSeries all{"evaluations", {}, {}, "#999", true},
          front{"Pareto front", {}, {}, "#c00", true}, box{"tolerance", {}, {}, "#06c"};
      for (const auto &e : evaluations)
        {
          const auto a = e.relative_error.find(p.a), b = e.relative_error.find(p.b);
          if (a == e.relative_error.end() || b == e.relative_error.end() ||
              !std::isfinite(a->second) || !std::isfinite(b->second))
            continue;
          all.x.push_back(100 * a->second), all.y.push_back(100 * b->second);
          if (std::find(p.front.begin(), p.front.end(), e.number) != p.front.end())
            front.x.push_back(100 * a->second), front.y.push_back(100 * b->second);
        }
      const double ta = 100 * target_named(targets, p.a).tolerance,
                   tb = 100 * target_named(targets, p.b).tolerance;
      box.x           = {-ta, ta, ta, -ta, -ta};
      box.y           = {-tb, -tb, tb, tb, -tb};
      return svg_plot("Which targets conflict: " + p.a + " and " + p.b +
                          (p.conflict ? " (met alone, never together)" : ""),
                      p.a + ": relative error [%]", p.b + ": relative error [%]",
                      {box, all, front});
    }

    // One pair of targets, as a fit_front.json "pairs" object and a
    // fit_front.csv row.
    Json pair_record(const dem::TargetPairFront &p)
    {
      Json j;
      j.str("target_a", p.a)
          .str("target_b", p.b)
          .num("evaluations", p.evaluations)
          .num("best_a", p.best_a)
          .num("evaluation_a", p.evaluation_a)
          .num("best_b", p.best_b)
          .num("evaluation_b", p.evaluation_b)
          .num("best_joint", p.best_joint)
          .num("evaluation_joint", p.evaluation_joint)
          .num("joint_excess", p.joint_excess)
          .str("conflict", p.conflict ? "yes" : "no")
          .nums("front", std::vector<double>(p.front.begin(), p.front.end()));
      return j;
    }

    // One parameter-target lever, as a fit_front.json "levers" object and a
    // fit_levers.csv row.
    Json lever_record(const dem::TargetLever &l)
    {
      Json j;
      j.str("parameter", l.parameter)
          .str("target", l.target)
          .num("pairs", l.pairs)
          .num("change_per_range", l.change_per_range)
          .num("largest_step", l.largest_step)
          .num("change_at_largest_step", l.change_per_range * l.largest_step)
          .num("seed_sd", l.seed_sd);
      return j;
    }
  } // namespace

  std::vector<dem::TargetEvaluation> read_fit_evaluations(const std::string &file,
                                                          const FitSettings &fit,
                                                          const std::string &what)
  {
    const auto   &targets = fit.targets;
    std::ifstream in(file);
    if (!in)
      throw std::invalid_argument(what + " " + file +
                                  ": cannot be read (give the fit.csv of a --fit run)");
    // Lines starting with '#' before the header: a note on where the rows
    // come from (docs/data keeps such logs).
    std::string header;
    std::size_t line_no = 0;
    while (std::getline(in, header) && (++line_no, header.rfind('#', 0) == 0))
      ;
    const auto names  = fit_log_cells(header);
    const auto column = [&](const std::string &n) -> long {
      const auto it = std::find(names.begin(), names.end(), n);
      return it == names.end() ? -1 : long(it - names.begin());
    };
    const long number = column("evaluation"), error = column("error"),
               stage = column("stage");
    if (number < 0)
      throw std::invalid_argument(what + " " + file +
                                  ": no 'evaluation' column (not a fit.csv)");
    std::vector<long> mean, sd, parameter;
    for (const auto &t : targets)
      {
        const std::string n = fit_csv_name(t.name);
        mean.push_back(column(n + "_mean"));
        sd.push_back(column(n + "_sd")); // optional
        if (mean.back() < 0)
          throw std::invalid_argument(what + " " + file + ": no column '" + n +
                                      "_mean' for Fit/Targets/" + t.name +
                                      " (the log of a fit with other targets?)");
      }
    for (const auto &p : fit.parameters)
      {
        parameter.push_back(column(fit_csv_name(p.name)));
        if (parameter.back() < 0)
          throw std::invalid_argument(what + " " + file + ": no column '" +
                                      fit_csv_name(p.name) + "' for Fit/parameters (" +
                                      p.name +
                                      ") (the log of a fit with other parameters?)");
      }
    std::vector<dem::TargetEvaluation> rows;
    for (std::string line; std::getline(in, line);)
      {
        ++line_no;
        if (line.empty())
          continue;
        const std::string at = what + " " + file + ", line " + std::to_string(line_no);
        const auto        c  = fit_log_cells(line);
        if (c.size() != names.size())
          throw std::invalid_argument(at + ": " + std::to_string(c.size()) +
                                      " cells, the header has " +
                                      std::to_string(names.size()) + " (a damaged log?)");
        if (error >= 0 && !c[std::size_t(error)].empty())
          continue; // a failed measurement has no properties
        dem::TargetEvaluation e;
        e.number = int(fit_log_number(c[std::size_t(number)], at));
        if (stage >= 0)
          e.stage = c[std::size_t(stage)];
        for (std::size_t i = 0; i < targets.size(); ++i)
          {
            const double scale = std::abs(targets[i].value);
            if (const auto &cell = c[std::size_t(mean[i])]; !cell.empty())
              e.relative_error[targets[i].name] =
                  (fit_log_number(cell, at) - targets[i].value) / scale;
            if (sd[i] >= 0 && !c[std::size_t(sd[i])].empty())
              e.relative_sd[targets[i].name] =
                  fit_log_number(c[std::size_t(sd[i])], at) / scale;
          }
        for (const long k : parameter)
          e.parameters.push_back(fit_log_number(c[std::size_t(k)], at));
        rows.push_back(e);
      }
    return rows;
  }

  dem::TargetFront write_target_front(
      const FitSettings &fit, const std::vector<dem::TargetEvaluation> &evaluations,
      const std::string &out, std::ostream &log)
  {
    const auto                  &targets = fit.targets;
    std::vector<dem::TargetSpec> specs;
    for (const auto &t : targets)
      specs.push_back({t.name, t.tolerance});
    const dem::TargetFront f = dem::analyse_target_front(specs, evaluations);

    std::vector<Json> pairs, bests;
    for (const auto &p : f.pairs)
      {
        pairs.push_back(pair_record(p));
        if (p.conflict)
          log << "demfem calibrate: " << p.a << " and " << p.b
              << " conflict: each within tolerance alone (evaluations " << p.evaluation_a
              << ", " << p.evaluation_b << "), never together (closest: evaluation "
              << p.evaluation_joint << ", " << p.best_joint << " tolerances)\n";
      }
    for (const auto &b : f.targets)
      {
        Json j;
        j.str("target", b.name)
            .num("evaluations", b.evaluations)
            .num("best_normalized_error", b.normalized_error)
            .num("evaluation", b.evaluation)
            .str("reached", b.reached ? "yes" : "no");
        bests.push_back(j);
        if (b.evaluations == 0)
          log << "demfem calibrate: " << b.name << " was measured in no evaluation\n";
        else if (!b.reached)
          log << "demfem calibrate: " << b.name << " is outside its tolerance in every "
              << b.evaluations << " evaluation(s) that measured it (closest: evaluation "
              << b.evaluation << ", " << b.normalized_error << " tolerances)\n";
      }
    // What each parameter alone does to each target (fit_levers.csv).
    std::vector<dem::ParameterSpec> params;
    for (const auto &p : fit.parameters)
      params.push_back({p.name, p.lo, p.hi});
    std::vector<Json> levers;
    for (const auto &l : dem::one_at_a_time_levers(params, specs, evaluations))
      levers.push_back(lever_record(l));
    Json j;
    j.num("evaluations", double(evaluations.size()))
        .str("errors_in", "tolerances: |value - target| / (tolerance x |target|)")
        .objs("targets", bests)
        .objs("pairs", pairs)
        .objs("levers", levers);
    // The CSV files are the JSON's pair and lever records, row by row.
    dem::vtkout::write_text_atomically(out + "/fit_front.csv",
                                       Json::csv(pairs, pair_record({})));
    dem::vtkout::write_text_atomically(out + "/fit_front.json", j.text() + "\n");
    dem::vtkout::write_text_atomically(out + "/fit_levers.csv",
                                       Json::csv(levers, lever_record({})));
    // The plot: the pair with the largest trade-off (pairs come sorted).
    if (!f.pairs.empty() && f.pairs.front().evaluations > 0)
      dem::vtkout::write_text_atomically(out + "/fit_front.svg",
                                         pair_svg(f.pairs.front(), targets, evaluations));
    return f;
  }
} // namespace demfem::apps
