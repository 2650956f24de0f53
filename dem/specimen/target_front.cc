// Which calibration targets conflict (target_front.h; docs/calibrate.md,
// "Which targets conflict").
#include "dem/specimen/target_front.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace demfem::dem
{
  namespace
  {
    // |error| / tolerance of target t in evaluation e, or NaN when e did not
    // measure it.
    double normalized(const TargetEvaluation &e, const TargetSpec &t)
    {
      const auto it = e.relative_error.find(t.name);
      if (it == e.relative_error.end() || !std::isfinite(it->second))
        return std::nan("");
      return std::abs(it->second) / t.tolerance;
    }

    TargetPairFront pair_front(const TargetSpec &ta, const TargetSpec &tb,
                               const std::vector<TargetEvaluation> &evaluations)
    {
      struct Point
      {
        double a, b;
        int    number;
      };
      std::vector<Point> p;
      for (const auto &e : evaluations)
        {
          const double a = normalized(e, ta), b = normalized(e, tb);
          if (std::isfinite(a) && std::isfinite(b))
            p.push_back({a, b, e.number});
        }
      TargetPairFront r;
      r.a           = ta.name;
      r.b           = tb.name;
      r.evaluations = int(p.size());
      if (p.empty())
        {
          r.best_a = r.best_b = r.best_joint = r.joint_excess = std::nan("");
          return r;
        }
      // The first evaluation on a tie: strict comparisons in log order.
      std::size_t ia = 0, ib = 0, ij = 0;
      for (std::size_t k = 1; k < p.size(); ++k)
        {
          if (p[k].a < p[ia].a)
            ia = k;
          if (p[k].b < p[ib].b)
            ib = k;
          if (std::max(p[k].a, p[k].b) < std::max(p[ij].a, p[ij].b))
            ij = k;
        }
      r.best_a           = p[ia].a;
      r.evaluation_a     = p[ia].number;
      r.best_b           = p[ib].b;
      r.evaluation_b     = p[ib].number;
      r.best_joint       = std::max(p[ij].a, p[ij].b);
      r.evaluation_joint = p[ij].number;
      r.joint_excess     = r.best_joint - std::max(r.best_a, r.best_b);
      r.conflict         = r.best_a <= 1 && r.best_b <= 1 && r.best_joint > 1;
      // Pareto front: no other point at most as far off in both and closer
      // in one (O(n^2): a fit logs at most a few hundred evaluations).
      std::vector<Point> front;
      for (const auto &q : p)
        {
          bool dominated = false;
          for (const auto &o : p)
            if (o.a <= q.a && o.b <= q.b && (o.a < q.a || o.b < q.b))
              {
                dominated = true;
                break;
              }
          if (!dominated)
            front.push_back(q);
        }
      std::stable_sort(front.begin(), front.end(),
                       [](const Point &x, const Point &y) { return x.a < y.a; });
      for (const auto &q : front)
        r.front.push_back(q.number);
      return r;
    }
  } // namespace

  std::vector<TargetLever> one_at_a_time_levers(
      const std::vector<ParameterSpec>    &parameters,
      const std::vector<TargetSpec>       &targets,
      const std::vector<TargetEvaluation> &evaluations)
  {
    for (const auto &p : parameters)
      if (!(p.hi > p.lo))
        throw std::invalid_argument(
            "parameter '" + p.name + "': the upper bound " + std::to_string(p.hi) +
            " must exceed the lower bound " + std::to_string(p.lo));
    const std::size_t                     P = parameters.size();
    std::vector<const TargetEvaluation *> known;
    for (const auto &e : evaluations)
      if (e.parameters.size() == P)
        known.push_back(&e);
    std::vector<TargetLever> levers;
    for (std::size_t k = 0; k < P; ++k)
      {
        // The pairs that differ in parameter k only, as (i, j, step / range).
        struct Pair
        {
          const TargetEvaluation *i, *j;
          double                  step;
        };
        std::vector<Pair> pairs;
        for (std::size_t a = 0; a < known.size(); ++a)
          for (std::size_t b = a + 1; b < known.size(); ++b)
            {
              const auto &pa = known[a]->parameters, &pb = known[b]->parameters;
              bool        only_k = known[a]->stage == known[b]->stage && pa[k] != pb[k];
              for (std::size_t m = 0; m < P && only_k; ++m)
                only_k = m == k || pa[m] == pb[m];
              if (only_k)
                pairs.push_back(
                    {known[a], known[b],
                     (pb[k] - pa[k]) / (parameters[k].hi - parameters[k].lo)});
            }
        for (const auto &t : targets)
          {
            TargetLever l;
            l.parameter = parameters[k].name;
            l.target    = t.name;
            double sxy = 0, sxx = 0, sd = 0;
            int    n_sd = 0;
            for (const auto &p : pairs)
              {
                const auto ei = p.i->relative_error.find(t.name),
                           ej = p.j->relative_error.find(t.name);
                if (ei == p.i->relative_error.end() || ej == p.j->relative_error.end() ||
                    !std::isfinite(ei->second) || !std::isfinite(ej->second))
                  continue;
                ++l.pairs;
                sxy += p.step * (ej->second - ei->second);
                sxx += p.step * p.step;
                l.largest_step = std::max(l.largest_step, std::abs(p.step));
                for (const auto *e : {p.i, p.j})
                  {
                    const auto s = e->relative_sd.find(t.name);
                    sd += s == e->relative_sd.end() ? std::nan("") : s->second;
                    ++n_sd;
                  }
              }
            if (l.pairs == 0)
              continue;
            l.change_per_range = sxy / sxx;
            l.seed_sd          = sd / n_sd;
            levers.push_back(l);
          }
      }
    return levers;
  }

  TargetFront analyse_target_front(const std::vector<TargetSpec>       &targets,
                                   const std::vector<TargetEvaluation> &evaluations)
  {
    std::set<std::string> names;
    for (const auto &t : targets)
      {
        if (!(t.tolerance > 0))
          throw std::invalid_argument("target '" + t.name + "': tolerance " +
                                      std::to_string(t.tolerance) + " must be > 0");
        if (!names.insert(t.name).second)
          throw std::invalid_argument("target '" + t.name + "' is given twice");
      }
    TargetFront f;
    for (const auto &t : targets)
      {
        TargetBest b;
        b.name             = t.name;
        b.normalized_error = std::nan("");
        for (const auto &e : evaluations)
          if (const double n = normalized(e, t); std::isfinite(n))
            {
              ++b.evaluations;
              if (!(n >= b.normalized_error)) // the first, or a strictly better one
                b.normalized_error = n, b.evaluation = e.number;
            }
        b.reached = b.normalized_error <= 1;
        f.targets.push_back(b);
      }
    for (std::size_t i = 0; i < targets.size(); ++i)
      for (std::size_t j = i + 1; j < targets.size(); ++j)
        f.pairs.push_back(pair_front(targets[i], targets[j], evaluations));
    // Largest trade-off first; pairs never measured together last.
    std::stable_sort(
        f.pairs.begin(), f.pairs.end(),
        [](const TargetPairFront &x, const TargetPairFront &y) {
          const double ex = std::isfinite(x.joint_excess) ? x.joint_excess : -1,
                       ey = std::isfinite(y.joint_excess) ? y.joint_excess : -1;
          return ex > ey;
        });
    return f;
  }
} // namespace demfem::dem
