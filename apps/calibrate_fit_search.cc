// The staged NLopt search of `demfem calibrate --fit` (apps/calibrate_fit.h;
// docs/calibrate.md, "Automatic calibration").
#include "apps/calibrate_fit.h"

#include "apps/calibrate_output.h"
#include "common/statistics.h"
#include "dem/io/vtk_output.h"

#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace demfem::apps
{
  FitMeasurement summarize_seeds(const std::map<std::string, std::vector<double>> &values,
                                 const std::string                                &error)
  {
    FitMeasurement out;
    out.error = error;
    for (const auto &[name, v] : values)
      {
        const auto i   = statistics::mean_interval(v);
        out.mean[name] = i.mean;
        out.sd[name]   = v.size() > 1 ? i.sd : 0.0;
      }
    return out;
  }

  bool fit_needs(const std::vector<std::string> &targets, const std::string &t)
  {
    for (const auto &n : targets)
      if ((t == "ucs" &&
           (n == "E" || n == "nu" || n == "ucs" || n == "crack initiation ratio")) ||
          (t == "brazilian" && n == "bts") ||
          (t == "direct tension" && n == "direct tension") ||
          (t == "triaxial series" && n == "mi"))
        return true;
    return false;
  }

  namespace
  {
    using Clock = std::chrono::steady_clock;

    bool is_elastic_target(const std::string &name)
    {
      return name == "E" || name == "nu";
    }

    nlopt::algorithm algorithm(const std::string &name, unsigned n)
    {
      // Powell's BOBYQA builds a quadratic model and needs two or more
      // variables; a one-parameter search uses Subplex.
      if (name == "bobyqa")
        return n >= 2 ? nlopt::LN_BOBYQA : nlopt::LN_SBPLX;
      if (name == "subplex")
        return nlopt::LN_SBPLX;
      if (name == "cobyla")
        return nlopt::LN_COBYLA;
      return nlopt::LN_NELDERMEAD;
    }

    std::string seconds_text(double t)
    {
      std::ostringstream o;
      o.precision(2);
      if (t < 120)
        o << std::fixed << t << " s";
      else
        o << std::fixed << t / 60 << " min";
      return o.str();
    }

    std::string csv_name(std::string n)
    {
      for (auto &c : n)
        if (c == ' ' || c == '/')
          c = '_';
      return n;
    }

    // The fit's state across stages: the current parameter values, the log
    // and the best evaluation so far.
    class Fit
    {
    public:
      Fit(const FitSettings &f, const FitProblem &problem, const std::string &out)
          : f_(f)
          , problem_(problem)
          , out_(out)
          , current_(problem.initial)
      {
        std::ostringstream h;
        h << "evaluation,stage";
        for (const auto &p : f.parameters)
          h << ',' << csv_name(p.name);
        for (const auto &t : f.targets)
          h << ',' << csv_name(t.name) << "_mean," << csv_name(t.name) << "_sd";
        h << ",objective,all_within_tolerance,seconds,error,note\n";
        csv_ = h.str();
      }

      // One stage: the listed parameters searched for the listed targets.
      void stage(const std::string &name, const std::vector<std::size_t> &params,
                 const std::vector<std::size_t> &targets, bool elastic)
      {
        stage_   = name;
        params_  = params;
        targets_ = targets;
        elastic_ = elastic;
        best_f_  = HUGE_VAL;
        best_x_.clear();
        n_eval_               = 0;
        t_stage_              = Clock::now();
        const auto          n = unsigned(params.size());
        nlopt::opt          opt(algorithm(f_.algorithm, n), n);
        std::vector<double> u(n), lo(n, 0.0), hi(n, 1.0);
        for (unsigned i = 0; i < n; ++i)
          {
            const auto &p = f_.parameters[params[i]];
            u[i] = std::clamp((current_[params[i]] - p.lo) / (p.hi - p.lo), 0.0, 1.0);
          }
        opt.set_lower_bounds(lo);
        opt.set_upper_bounds(hi);
        opt.set_maxeval(f_.evaluations);
        // Normalised parameters: 1e-3 of a bound range is below the
        // resolution any target tolerance needs.
        opt.set_xtol_abs(1e-3);
        opt.set_initial_step(0.25);
        opt.set_min_objective(&Fit::objective, this);
        std::string reason = "budget";
        double      f      = 0;
        try
          {
            const auto r = opt.optimize(u, f);
            reason       = r == nlopt::MAXEVAL_REACHED ? "budget" : "converged";
          }
        catch (const nlopt::forced_stop &)
          {
            reason = "targets reached";
          }
        catch (const std::exception &e) // e.g. nlopt::roundoff_limited
          {
            reason = std::string("optimizer stopped: ") + e.what();
          }
        if (best_x_.empty())
          throw std::runtime_error("calibrate --fit: stage " + name +
                                   " made no evaluation");
        // The stage's best parameters stay for the next.
        for (unsigned i = 0; i < n; ++i)
          current_[params[i]] = best_x_[i];
        Json j;
        j.str("stage", name)
            .str("stop", reason)
            .num("evaluations", n_eval_)
            .num("best_objective", best_f_)
            .num("seconds", seconds_since(t_stage_));
        stages_.push_back(j);
        std::cerr << "demfem calibrate --fit: stage " << name << ": " << reason
                  << " after " << n_eval_ << " evaluations, best objective " << best_f_
                  << "\n";
      }

      // Measurement of the current parameters on every target.
      FitMeasurement final_measurement() const
      {
        std::vector<std::string> all;
        for (const auto &t : f_.targets)
          all.push_back(t.name);
        return problem_.measure(current_, all, false);
      }

      const std::vector<double> &current() const { return current_; }
      const std::vector<Json>   &stages() const { return stages_; }
      const std::vector<double> &objectives() const { return history_; }

    private:
      static double objective(unsigned n, const double *u, double *, void *data)
      {
        auto &self = *static_cast<Fit *>(data);
        return self.evaluate(std::vector<double>(u, u + n));
      }

      double evaluate(const std::vector<double> &u)
      {
        const auto          t0     = Clock::now();
        std::vector<double> values = current_, x(u.size());
        for (std::size_t i = 0; i < u.size(); ++i)
          {
            const auto &p      = f_.parameters[params_[i]];
            x[i]               = p.lo + u[i] * (p.hi - p.lo);
            values[params_[i]] = x[i];
          }
        std::vector<std::string> names;
        for (auto t : targets_)
          names.push_back(f_.targets[t].name);
        const FitMeasurement m = problem_.measure(values, names, elastic_);
        // Weighted sum of squared relative errors in units of each target's
        // tolerance: 1 per target means "at the tolerance". A failed
        // evaluation (instability, a test that did not reach a peak) is
        // far worse than any measured one.
        double f      = 0;
        bool   within = m.error.empty();
        for (auto t : targets_)
          {
            const auto  &T  = f_.targets[t];
            const auto   it = m.mean.find(T.name);
            const double r  = it == m.mean.end() || !std::isfinite(it->second)
                                  ? HUGE_VAL
                                  : (it->second - T.value) / std::abs(T.value);
            f += T.weight * std::pow(std::min(std::abs(r), 1e3) / T.tolerance, 2);
            within = within && std::abs(r) <= T.tolerance;
          }
        if (!m.error.empty())
          f = 1e12;
        ++n_eval_;
        history_.push_back(f);
        if (f < best_f_)
          best_f_ = f, best_x_ = x;
        log(values, m, f, within, seconds_since(t0));
        if (within)
          throw nlopt::forced_stop();
        return f;
      }

      void log(const std::vector<double> &values, const FitMeasurement &m, double f,
               bool within, double seconds)
      {
        std::ostringstream row;
        row.precision(17);
        row << history_.size() << ',' << stage_;
        for (double v : values)
          row << ',' << v;
        for (const auto &t : f_.targets)
          {
            const auto a = m.mean.find(t.name), b = m.sd.find(t.name);
            row << ',';
            if (a != m.mean.end())
              row << a->second;
            row << ',';
            if (b != m.sd.end())
              row << b->second;
          }
        auto cell = [](std::string t) {
          for (auto &c : t)
            if (c == ',' || c == '\n')
              c = ' ';
          return t;
        };
        row << ',' << f << ',' << (within ? 1 : 0) << ',' << seconds << ','
            << cell(m.error) << ',' << cell(m.note) << '\n';
        csv_ += row.str();
        dem::vtkout::write_text_atomically(out_ + "/fit.csv", csv_);
        // Progress with ETA against the stage's evaluation budget.
        const double spent = seconds_since(t_stage_);
        const double eta   = spent / n_eval_ * (f_.evaluations - n_eval_);
        std::cerr << "demfem calibrate --fit: [" << stage_ << "] evaluation " << n_eval_
                  << "/" << f_.evaluations << ": objective " << f << " (best " << best_f_
                  << ")";
        for (auto t : targets_)
          {
            const auto &n = f_.targets[t].name;
            if (m.mean.count(n))
              std::cerr << ", " << n << " " << m.mean.at(n);
          }
        if (!m.error.empty())
          std::cerr << ", failed: " << m.error;
        else if (!m.note.empty())
          std::cerr << ", note: " << m.note;
        std::cerr << "; ETA at most " << seconds_text(eta) << "\n";
      }

      const FitSettings       &f_;
      const FitProblem        &problem_;
      std::string              out_, stage_, csv_;
      std::vector<double>      current_;
      std::vector<std::size_t> params_, targets_;
      bool                     elastic_ = false;
      double                   best_f_  = HUGE_VAL;
      std::vector<double>      best_x_, history_;
      int                      n_eval_ = 0;
      Clock::time_point        t_stage_;
      std::vector<Json>        stages_;
    };

    std::string convergence_svg(const std::vector<double> &f)
    {
      PlotSeries all{"objective", {}, {}, "#999", true},
          best{"best so far", {}, {}, "#c00"};
      double b = HUGE_VAL;
      for (std::size_t k = 0; k < f.size(); ++k)
        {
          b = std::min(b, f[k]);
          all.x.push_back(double(k + 1)), all.y.push_back(std::log10(f[k] + 1e-12));
          best.x.push_back(double(k + 1)), best.y.push_back(std::log10(b + 1e-12));
        }
      return svg_plot("Automatic calibration: objective per evaluation", "evaluation",
                      "log10 objective (1 = one target at its tolerance)", {all, best});
    }
  } // namespace

  FitSearchResult run_fit_search(const FitSettings &f, const FitProblem &problem,
                                 const std::string &out)
  {
    const auto t0 = Clock::now();
    std::filesystem::create_directories(out);
    std::vector<std::size_t> elastic_p, other_p, elastic_t, other_t;
    for (std::size_t i = 0; i < f.parameters.size(); ++i)
      (problem.is_elastic_parameter(f.parameters[i].name) ? elastic_p : other_p)
          .push_back(i);
    for (std::size_t i = 0; i < f.targets.size(); ++i)
      (is_elastic_target(f.targets[i].name) ? elastic_t : other_t).push_back(i);
    std::cerr << "demfem calibrate --fit: " << f.parameters.size() << " parameters, "
              << f.targets.size() << " targets, " << f.seeds
              << " packings per evaluation, at most " << f.evaluations
              << " evaluations per stage (" << f.algorithm << ")\n";
    Fit                      fit(f, problem, out);
    std::vector<std::size_t> all_p(f.parameters.size()), all_t(f.targets.size());
    for (std::size_t i = 0; i < all_p.size(); ++i)
      all_p[i] = i;
    for (std::size_t i = 0; i < all_t.size(); ++i)
      all_t[i] = i;
    auto within = [&](const FitMeasurement &m) {
      if (!m.error.empty())
        return false;
      for (const auto &t : f.targets)
        {
          const auto it = m.mean.find(t.name);
          if (it == m.mean.end() ||
              !(std::abs(it->second - t.value) <= t.tolerance * std::abs(t.value)))
            return false;
        }
      return true;
    };
    // Cheap stage first: the elastic constants from small-strain tests,
    // searched over the stiffness parameters only; then the strengths with
    // the stiffnesses fixed. Strength tests measure E and nu in their own
    // fit window, where early cracking softens the response: when the full
    // tests miss a target, a last stage searches every parameter on them.
    FitMeasurement m;
    if (!elastic_p.empty() && !elastic_t.empty())
      {
        fit.stage("elastic", elastic_p, elastic_t, true);
        if (!other_p.empty() && !other_t.empty())
          fit.stage("strength", other_p, other_t, false);
        m = fit.final_measurement();
        if (!within(m))
          {
            std::cerr
                << "demfem calibrate --fit: the full tests miss a target; searching "
                   "every parameter on them\n";
            fit.stage("all", all_p, all_t, false);
            m = fit.final_measurement();
          }
      }
    else
      {
        fit.stage("all", all_p, all_t, false);
        m = fit.final_measurement();
      }

    // fit.json: the best parameters, measured on every target.
    FitSearchResult result{fit.current(), m, within(m)};
    Json            targets, best;
    for (const auto &t : f.targets)
      {
        const auto   it = m.mean.find(t.name);
        const double v  = it == m.mean.end() ? std::nan("") : it->second;
        const double r  = (v - t.value) / std::abs(t.value);
        const bool   ok = std::abs(r) <= t.tolerance;
        Json         j;
        j.num("target", t.value)
            .num("tolerance", t.tolerance)
            .num("weight", t.weight)
            .num("seed_mean", v)
            .num("seed_sd", m.sd.count(t.name) ? m.sd.at(t.name) : std::nan(""))
            .num("relative_error", r)
            .str("within_tolerance", ok ? "yes" : "no");
        targets.obj(t.name, j);
        std::cerr << "demfem calibrate --fit: " << t.name << ": " << v << " (target "
                  << t.value << ", relative error " << r << ", "
                  << (ok ? "within" : "OUTSIDE") << " tolerance " << t.tolerance << ")\n";
      }
    for (std::size_t i = 0; i < f.parameters.size(); ++i)
      best.num(f.parameters[i].name, result.best[i]);
    Json j;
    j.str("status", result.all_within ? "ok" : "targets_not_reached")
        .str("algorithm", f.algorithm)
        .num("seeds", f.seeds)
        .num("evaluations", double(fit.objectives().size()))
        .num("wall_time_s", seconds_since(t0))
        .obj("best_parameters", best)
        .obj("targets", targets)
        .objs("stages", fit.stages());
    if (!m.error.empty())
      j.str("error", m.error);
    if (!m.note.empty())
      j.str("note", m.note);
    dem::vtkout::write_text_atomically(out + "/fit.json", j.text() + "\n");
    dem::vtkout::write_text_atomically(out + "/fit_convergence.svg",
                                       convergence_svg(fit.objectives()));
    return result;
  }
} // namespace demfem::apps
