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
#include <iomanip>
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

    // The fit's state across stages: the current parameter values, the log
    // and the best evaluation so far.
    class Fit
    {
    public:
      Fit(const FitSettings &f, const FitProblem &problem, const std::string &out)
          : f_(f)
          , problem_(problem)
          , out_(out)
          , csv_(fit_csv_header(f))
          , current_(problem.initial)
      {
        if (!f.replay.empty())
          std::cerr << "demfem calibrate --fit: resuming: " << f.replay.size()
                    << " evaluations of " << f.resume_from << " to replay\n";
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

      // Measurement of the current parameters on every target, logged in
      // fit.csv as stage "check" (it costs a full evaluation, so a resumed
      // fit replays it too). When the last stage's best evaluation ran the
      // full tests and measured every target (a UCS test gives E and nu
      // with the UCS), it is that measurement: the same parameters on the
      // same packings by the same tests measure the same values (a
      // measurement is a deterministic function of the parameters on fixed
      // seeds), so it is taken, not measured again (in 3D an evaluation of
      // three packings takes 20-45 minutes on two cores).
      FitMeasurement final_measurement()
      {
        std::vector<std::string> all;
        std::vector<std::size_t> every;
        for (std::size_t t = 0; t < f_.targets.size(); ++t)
          all.push_back(f_.targets[t].name), every.push_back(t);
        const std::string last_stage = stage_;
        stage_                       = "check";
        if (!elastic_ && !best_x_.empty() && measures_every_target(best_m_))
          {
            // A resumed log's check row of these parameters is this one.
            if (next_replay_ < f_.replay.size() &&
                f_.replay[next_replay_].stage == stage_ &&
                f_.replay[next_replay_].values == current_)
              ++next_replay_;
            FitMeasurement m = best_m_;
            m.note = "the measurement of evaluation " + std::to_string(best_row_) + " (" +
                     last_stage +
                     "): the same parameters on the same packings by the same tests" +
                     (m.note.empty() ? "" : "; " + m.note);
            bool         within = false;
            const double f      = objective_of(m, every, within);
            log(current_, m, f, within, 0, false);
            std::cerr << "demfem calibrate --fit: [check] the best parameters on every "
                         "target: objective "
                      << f << " (evaluation " << best_row_ << ", not measured again)\n";
            return m;
          }
        double       s      = 0;
        bool         re     = false;
        const auto   m      = measure(current_, all, false, s, re);
        bool         within = false;
        const double f      = objective_of(m, every, within);
        log(current_, m, f, within, s, re);
        std::cerr
            << "demfem calibrate --fit: [check] the best parameters on every target: "
            << "objective " << f << (re ? " (replayed)" : "") << "\n";
        return m;
      }

      int replayed() const { return n_replayed_; }

      const std::vector<double> &current() const { return current_; }
      const std::vector<Json>   &stages() const { return stages_; }
      const std::vector<double> &objectives() const { return history_; }

    private:
      static double objective(unsigned n, const double *u, double *, void *data)
      {
        auto &self = *static_cast<Fit *>(data);
        return self.evaluate(std::vector<double>(u, u + n));
      }

      // The measurement of `values`: the next row of the resumed log when
      // it is this stage's evaluation of the same values (the search then
      // follows the earlier run's path), else measured now; a row that
      // differs ends the replay.
      FitMeasurement measure(const std::vector<double>      &values,
                             const std::vector<std::string> &names, bool elastic,
                             double &seconds, bool &replayed)
      {
        replayed = false;
        if (next_replay_ < f_.replay.size())
          {
            const FitLogRow &row = f_.replay[next_replay_];
            if (row.stage == stage_ && row.values == values)
              {
                ++next_replay_, ++n_replayed_;
                replayed = true;
                seconds  = row.seconds;
                return row.measured;
              }
            std::cerr << "demfem calibrate --fit: [" << stage_ << "] the search leaves "
                      << f_.resume_from << " at its row " << next_replay_ + 1
                      << " (other parameters or stage): measuring from here\n";
            next_replay_ = f_.replay.size();
          }
        const auto t0 = Clock::now();
        auto       m  = problem_.measure(values, names, elastic);
        seconds       = seconds_since(t0);
        ++n_fresh_;
        fresh_seconds_ += seconds;
        return m;
      }

      // A measurement without error that has a finite mean of every target.
      bool measures_every_target(const FitMeasurement &m) const
      {
        if (!m.error.empty())
          return false;
        for (const auto &t : f_.targets)
          {
            const auto it = m.mean.find(t.name);
            if (it == m.mean.end() || !std::isfinite(it->second))
              return false;
          }
        return true;
      }

      // Weighted sum of squared relative errors in units of each target's
      // tolerance: 1 per target means "at the tolerance". A failed
      // evaluation (instability, a test that did not reach a peak) is far
      // worse than any measured one.
      double objective_of(const FitMeasurement           &m,
                          const std::vector<std::size_t> &targets, bool &within) const
      {
        double f = 0;
        within   = m.error.empty();
        for (auto t : targets)
          {
            const auto  &T  = f_.targets[t];
            const auto   it = m.mean.find(T.name);
            const double r  = it == m.mean.end() || !std::isfinite(it->second)
                                  ? HUGE_VAL
                                  : (it->second - T.value) / std::abs(T.value);
            f += T.weight * std::pow(std::min(std::abs(r), 1e3) / T.tolerance, 2);
            within = within && std::abs(r) <= T.tolerance;
          }
        return m.error.empty() ? f : 1e12;
      }

      double evaluate(const std::vector<double> &u)
      {
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
        double               seconds  = 0;
        bool                 replayed = false;
        const FitMeasurement m      = measure(values, names, elastic_, seconds, replayed);
        bool                 within = false;
        const double         f      = objective_of(m, targets_, within);
        ++n_eval_;
        history_.push_back(f);
        log(values, m, f, within, seconds, replayed);
        if (f < best_f_)
          best_f_ = f, best_x_ = x, best_m_ = m, best_row_ = rows_;
        progress(m, f, replayed);
        if (within)
          throw nlopt::forced_stop();
        return f;
      }

      // A row of fit.csv (a replayed row marked so in its note).
      void log(const std::vector<double> &values, const FitMeasurement &m, double f,
               bool within, double seconds, bool replayed)
      {
        std::ostringstream row;
        row.precision(17);
        row << ++rows_ << ',' << stage_;
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
        const std::string note =
            replayed ? (m.note.empty() ? "replayed" : "replayed; " + m.note) : m.note;
        row << ',' << f << ',' << (within ? 1 : 0) << ',' << std::setprecision(4)
            << seconds << ',' << cell(m.error) << ',' << cell(note) << '\n';
        csv_ += row.str();
        dem::vtkout::write_text_atomically(out_ + "/fit.csv", csv_);
      }

      // The progress line, with an ETA against the stage's evaluation
      // budget from the evaluations measured now (a replayed one costs
      // nothing).
      void progress(const FitMeasurement &m, double f, bool replayed) const
      {
        std::cerr << "demfem calibrate --fit: [" << stage_ << "] evaluation " << n_eval_
                  << "/" << f_.evaluations << (replayed ? " (replayed)" : "")
                  << ": objective " << f << " (best " << best_f_ << ")";
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
        if (n_fresh_ > 0)
          std::cerr << "; ETA at most "
                    << seconds_text(fresh_seconds_ / n_fresh_ *
                                    (f_.evaluations - n_eval_));
        std::cerr << "\n";
      }

      const FitSettings       &f_;
      const FitProblem        &problem_;
      std::string              out_, csv_, stage_;
      std::vector<double>      current_;
      std::vector<std::size_t> params_, targets_;
      bool                     elastic_ = false;
      double                   best_f_  = HUGE_VAL;
      std::vector<double>      best_x_, history_;
      FitMeasurement           best_m_;       ///< the measurement at best_x_
      int                      best_row_ = 0; ///< its row of fit.csv
      int                      n_eval_ = 0, rows_ = 0;
      std::size_t              next_replay_ = 0; ///< the resumed log's next row
      int                      n_replayed_ = 0, n_fresh_ = 0;
      double                   fresh_seconds_ = 0; ///< measured now, for the ETA
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
    // Which targets conflict over every evaluation of this fit (replayed
    // ones included): fit_front.*, the conflicting pairs named in fit.json.
    std::vector<Json> conflicts;
    for (const auto &p :
         write_target_front(f, read_fit_evaluations(out + "/fit.csv", f, "fit.csv"), out,
                            std::cerr)
             .pairs)
      if (p.conflict)
        {
          Json c;
          c.str("target_a", p.a).str("target_b", p.b).num("best_joint", p.best_joint);
          conflicts.push_back(c);
        }
    Json j;
    j.str("status", result.all_within ? "ok" : "targets_not_reached")
        .str("algorithm", f.algorithm)
        .num("seeds", f.seeds)
        .num("brazilian_seeds", f.brazilian_disks())
        .num("evaluations", double(fit.objectives().size()))
        .num("replayed_evaluations", fit.replayed())
        .str("resumed_from", f.resume_from)
        .num("wall_time_s", seconds_since(t0))
        .obj("best_parameters", best)
        .obj("targets", targets)
        .objs("conflicting_targets", conflicts)
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
