// Closed forms, Pareto front, CSV and SVG chart of `demfem study`.
#include "apps/study.h"
#include "common/atomic_file.h"
#include "common/statistics.h"
#include "coupling/kirsch.h"
#include "dem/engine/types.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

namespace demfem::apps::study
{
  double kirsch_mean_convergence(const Eigen::Matrix2d &sigma0, double a, double E,
                                 double nu)
  {
    // Kirsch excavation-induced displacement of the wall r = a (plane
    // strain, tension and outward positive, S1 along t = 0):
    //   u_r = a/(4G) [(S1+S2) + (S1-S2)(3 - 4 nu) cos 2t];
    // the cos 2t term averages to zero over the wall, so the mean inward
    // displacement is -a (S1+S2)/(4G). nu enters only through G, which is the
    // same for the plane-strain pair (E', nu') and the 3D pair (E, nu).
    const double G = E / (2 * (1 + nu));
    return -a * (sigma0(0, 0) + sigma0(1, 1)) / (4 * G);
  }

  double kirsch_convergence_at(const Eigen::Matrix2d &sigma0, double a, double E,
                               double                                    nu,
                               const std::vector<std::array<double, 2>> &points)
  {
    const auto   p = coupling::kirsch::principal(sigma0);
    const double G = E / (2 * (1 + nu));
    double       u = 0;
    for (const auto &x : points)
      {
        const double r = std::hypot(x[0], x[1]), q = a * a / (r * r);
        const double t = std::atan2(x[1], x[0]) - p.phi;
        u += a * a / (4 * G * r) *
             ((p.s1 + p.s2) + (p.s1 - p.s2) * (4 * (1 - nu) - q) * std::cos(2 * t));
      }
    return points.empty() ? 0.0 : -u / double(points.size()); // inward positive
  }

  double kirsch_differential_stress(const Eigen::Matrix2d &sigma0, double a, double r,
                                    double theta)
  {
    return coupling::kirsch::differential_stress(sigma0, a, r, theta);
  }

  double kirsch_damage_radius(const Eigen::Matrix2d &sigma0, double a, double threshold)
  {
    const double R = coupling::kirsch::damage_radius(sigma0, a, threshold);
    if (!(R < HUGE_VAL))
      {
        const double far = coupling::kirsch::far_field_differential_stress(sigma0);
        throw dem::InputError(
            "Study/damage threshold: the far-field differential stress " +
            std::to_string(far) + " Pa already reaches the damage threshold " +
            std::to_string(threshold) +
            " Pa: the whole rock mass is damaged and no finite DEM region encloses "
            "it; set 'DEM region/radius' to a number");
      }
    return R;
  }

  AutoRadius auto_region_radius(const Eigen::Matrix2d &sigma0, double a, double ucs,
                                double fraction, double margin_grains, double d)
  {
    if (!(ucs > 0))
      throw dem::InputError("DEM region/radius = auto needs the UCS: set Study/ucs "
                            "[Pa] (> 0) or a DEM region/material file with \"ucs\"");
    AutoRadius r;
    r.threshold     = fraction * ucs;
    r.damage_radius = kirsch_damage_radius(sigma0, a, r.threshold);
    r.radius        = std::max(r.damage_radius + margin_grains * d, a + 4 * d);
    return r;
  }

  void mark_pareto(std::vector<Row> &rows)
  {
    for (auto &p : rows)
      {
        p.pareto = p.status == "stable" && p.equilibrated && std::isfinite(p.error);
        for (const auto &q : rows)
          if (p.pareto && &q != &p && q.status == "stable" && q.equilibrated &&
              std::isfinite(q.error) && q.result.wall_time_s <= p.result.wall_time_s &&
              std::abs(q.error) <= std::abs(p.error) &&
              (q.result.wall_time_s < p.result.wall_time_s ||
               std::abs(q.error) < std::abs(p.error)))
            p.pareto = false;
      }
  }

  namespace
  {
    // Numbers are written only when finite (no NaN in the outputs).
    std::string num(double v, bool defined = true)
    {
      if (!defined || !std::isfinite(v))
        return "";
      std::ostringstream s;
      s << std::setprecision(6) << v;
      return s.str();
    }

    std::string quoted(const std::string &t)
    {
      std::string q = "\"";
      for (char c : t)
        q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
      return q + "\"";
    }

    // A chart marker whose shape names the scheme (circle explicit, square
    // quasi-static, triangle condensed): the colour already tells the Pareto
    // front from the other runs, and a sweep over schemes puts runs of the
    // same settings side by side.
    std::string marker(const std::string &scheme, double x, double y, double r,
                       const std::string &fill, const std::string &title)
    {
      std::ostringstream o;
      std::string        tag = "circle";
      if (scheme == "condensed")
        tag = "polygon", o << "<polygon points=\"" << x << "," << y - 1.2 * r << " "
                           << x - 1.1 * r << "," << y + 0.8 * r << " " << x + 1.1 * r
                           << "," << y + 0.8 * r << "\"";
      else if (scheme == "quasi-static")
        tag = "rect", o << "<rect x=\"" << x - 0.9 * r << "\" y=\"" << y - 0.9 * r
                        << "\" width=\"" << 1.8 * r << "\" height=\"" << 1.8 * r << "\"";
      else
        o << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"" << r << "\"";
      o << " fill=\"" << fill << "\"";
      if (title.empty())
        o << "/>";
      else
        o << "><title>" << title << "</title></" << tag << ">";
      return o.str() + "\n";
    }
  } // namespace

  void write_csv(const std::string &file, const std::vector<Row> &rows)
  {
    std::ostringstream o; // replaced atomically below
    o << "run,region_radius_m,region_factor,region_auto,a_over_d,grain_diameter_m,"
         "subcycles,timestep_safety,status,n_particles,steps,wall_time_s,"
         "wall_convergence_m,kirsch_convergence_m,error_rel,pareto,seed,equilibrated,"
         "final_ratio,variant,scheme,relaxation,stiffness_contrast,breakable,"
         "cracks_total,cracks_excavation,cracks_tensile,cracks_shear,"
         "damage_zone_depth_m,reference_depth_m,cracks_rel_diff,agrees,"
         "region_too_small,damaged_area_m2,notch_depth_m,notch_angle_deg,"
         "connected_cracks,damage_zone_depth_all_m,genesis_steps,"
         "genesis_reused,genesis_wall_time_s,kirsch_at_grains_m,error_at_grains_rel,"
         "reference_area_m2,area_rel_diff,in_situ_error,servo_interface_strain_rel,"
         "elastic_zone_key,elastic_zone_depth_m,elastic_zone_area_m2,"
         "connected_cracks_in_elastic_zone,diagnosis\n";
    for (const auto &r : rows)
      {
        const bool ok  = r.status == "stable";
        const bool ran = r.status != "invalid";
        o << r.index << "," << num(r.region_radius) << "," << num(r.region_factor) << ","
          << (r.region_auto ? "yes" : "no") << "," << num(r.resolution) << ","
          << num(r.grain_d) << "," << r.subcycles << "," << num(r.safety) << ","
          << r.status << "," << (ran ? std::to_string(r.result.n_particles) : "") << ","
          << (ran ? std::to_string(r.result.steps) : "") << ","
          << num(r.result.wall_time_s, ran) << ","
          << num(r.result.wall_convergence_mean, ok) << "," << num(r.kirsch, !r.breakable)
          << "," << num(r.error, ok) << "," << (r.pareto ? "yes" : "no") << "," << r.seed
          << "," << (ok ? (r.equilibrated ? "yes" : "no") : "") << ","
          << num(r.final_ratio, ok && r.final_ratio >= 0) << "," << r.variant << ","
          << r.scheme << "," << num(r.relaxation, uses_relaxation(r.scheme)) << ","
          << num(r.contrast) << "," << (r.breakable ? "yes" : "no") << ",";
        // damage columns: breakable runs that finished (the counts of a
        // diverged run are not results)
        const bool dmg   = r.breakable && ok;
        auto       count = [&](std::size_t n) {
          return dmg ? std::to_string(n) : std::string();
        };
        const bool cmp = dmg && std::isfinite(r.error);
        // genesis_steps: the region is packed in a model of its own before
        // the run (coupling/region_genesis.cc), a cost that `steps` does not
        // hold; reused from an earlier run of the sweep when the packing is
        // the same (coupling/genesis_cache.h; wall_time_s counts it either
        // way).
        o << count(r.result.cracks_total) << "," << count(r.cracks_excavation) << ","
          << count(r.result.cracks_tensile) << "," << count(r.result.cracks_shear) << ","
          << num(r.result.damage_zone_depth, dmg) << "," << num(r.reference_depth, cmp)
          << "," << num(r.cracks_diff, cmp) << ","
          << (cmp ? (r.agrees ? "yes" : "no") : "") << ","
          << (dmg ? (r.region_too_small ? "yes" : "no") : "") << ","
          << num(r.result.damage.damaged_area, dmg) << ","
          << num(r.result.damage.notch_depth, dmg) << ","
          << num(r.result.damage.notch_angle, dmg) << ","
          << count(r.result.damage.connected_cracks) << ","
          << num(r.result.damage.depth_all, dmg) << ","
          << (ran ? std::to_string(r.result.genesis_steps) : "") << ","
          << (ran ? (r.result.genesis_reused ? "yes" : "no") : "") << ","
          << num(r.result.genesis_wall_time_s, ran) << ","
          << num(r.kirsch_at_grains, ok && !r.breakable) << ","
          << num(r.error_at_grains, ok && !r.breakable) << ","
          << num(r.reference_area, cmp) << ","
          << num(r.area_diff, cmp && std::isfinite(r.area_diff)) << ",";
        // The in-situ state (docs/tunnel.md, "In-situ stress servo"): the
        // region's error against sigma0 and, where the servo ran, the
        // interface strain it needed over the in-situ strain.
        const bool servoed = ok && r.result.servo.tolerance > 0;
        o << num(r.result.in_situ_error, ok) << ","
          << num(r.result.servo.relative_strain, servoed) << ",";
        // The elastic zone of the material's first crack-initiation stress
        // (coupling/initiation_zone.h) and the damage zone's cracks in it:
        // breakable runs with a material file whose far field stays below it.
        const bool zone = dmg && !r.result.initiation_zones.empty() &&
                          !r.result.initiation_zones.front().far_field_exceeds;
        const auto *z = zone ? &r.result.initiation_zones.front() : nullptr;
        o << (z ? z->name : std::string()) << "," << num(z ? z->depth : 0.0, zone) << ","
          << num(z ? z->area : 0.0, zone) << ","
          << (z ? std::to_string(z->zone_cracks_inside) : std::string()) << ","
          << quoted(r.diagnosis) << "\n";
      }
    write_file_atomically(file, o.str());
  }

  void write_chart(const std::string &file, const std::vector<Row> &rows, bool breakable,
                   double ref_time)
  {
    std::vector<const Row *> pts;
    for (const auto &r : rows)
      if (r.status == "stable" && r.equilibrated && std::isfinite(r.error) &&
          r.result.wall_time_s > 0)
        pts.push_back(&r);
    const double W = 720, H = 480, L = 80, R = 200, T = 40, B = 60;
    // log-log axes over whole decades; |error| floored at 1e-4 (0.01 %)
    auto   ey = [](const Row *r) { return std::max(std::abs(r->error), 1e-4); };
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const auto *p : pts)
      {
        x0 = std::min(x0, std::log10(p->result.wall_time_s));
        x1 = std::max(x1, std::log10(p->result.wall_time_s));
        y0 = std::min(y0, std::log10(ey(p)));
        y1 = std::max(y1, std::log10(ey(p)));
      }
    if (pts.empty())
      x0 = x1 = y0 = y1 = 0;
    if (breakable && ref_time > 0) // the reference's time is on the chart
      x0 = std::min(x0, std::log10(ref_time)), x1 = std::max(x1, std::log10(ref_time));
    x0 = std::floor(x0), y0 = std::floor(y0), x1 = std::max(std::ceil(x1), x0 + 1),
    y1     = std::max(std::ceil(y1), y0 + 1);
    auto X = [&](double t) { return L + (W - L - R) * (std::log10(t) - x0) / (x1 - x0); };
    auto Y = [&](double e) {
      return H - B - (H - T - B) * (std::log10(e) - y0) / (y1 - y0);
    };

    std::ostringstream o; // replaced atomically below
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << L << "\" y=\"24\" font-size=\"15\">"
      << (breakable ? "breakable: wall time versus damage-zone depth "
                      "difference from the full-DEM reference"
                    : "demfem study: wall time versus error of the wall convergence "
                      "against Kirsch")
      << "</text>\n";
    for (int k = int(x0); k <= int(x1); ++k) // decade grid
      o << "<line x1=\"" << X(std::pow(10, k)) << "\" y1=\"" << T << "\" x2=\""
        << X(std::pow(10, k)) << "\" y2=\"" << H - B << "\" stroke=\"#ddd\"/>\n"
        << "<text x=\"" << X(std::pow(10, k)) << "\" y=\"" << H - B + 16
        << "\" text-anchor=\"middle\">1e" << k << "</text>\n";
    for (int k = int(y0); k <= int(y1); ++k)
      o << "<line x1=\"" << L << "\" y1=\"" << Y(std::pow(10, k)) << "\" x2=\"" << W - R
        << "\" y2=\"" << Y(std::pow(10, k)) << "\" stroke=\"#ddd\"/>\n"
        << "<text x=\"" << L - 6 << "\" y=\"" << Y(std::pow(10, k)) + 4
        << "\" text-anchor=\"end\">" << 100 * std::pow(10, k) << " %</text>\n";
    o << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W - L - R
      << "\" height=\"" << H - T - B << "\" fill=\"none\" stroke=\"black\"/>\n"
      << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 20
      << "\" text-anchor=\"middle\">wall-clock time [s]</text>\n"
      << "<text transform=\"translate(20," << (T + H - B) / 2
      << ") rotate(-90)\" text-anchor=\"middle\">"
      << (breakable ? "|damage-zone depth - reference| / reference"
                    : "|error| of mean wall convergence")
      << "</text>\n";
    if (breakable && ref_time > 0)
      o << "<line x1=\"" << X(ref_time) << "\" y1=\"" << T << "\" x2=\"" << X(ref_time)
        << "\" y2=\"" << H - B << "\" stroke=\"#090\" stroke-dasharray=\"6,4\"/>\n"
        << "<text x=\"" << X(ref_time) - 4 << "\" y=\"" << T + 14
        << "\" text-anchor=\"end\" fill=\"#090\">full-DEM reference</text>\n";
    std::vector<const Row *> front;
    for (const auto *p : pts)
      if (p->pareto)
        front.push_back(p);
    std::sort(front.begin(), front.end(), [](const Row *a, const Row *b) {
      return a->result.wall_time_s < b->result.wall_time_s;
    });
    if (front.size() > 1)
      {
        o << "<polyline fill=\"none\" stroke=\"#c00\" stroke-width=\"1.5\" points=\"";
        for (const auto *p : front)
          o << X(p->result.wall_time_s) << "," << Y(ey(p)) << " ";
        o << "\"/>\n";
      }
    for (const auto *p : pts)
      {
        std::ostringstream title;
        title << "run " << p->index << ": b/a=" << p->region_factor
              << " a/d=" << p->resolution << " k=" << p->subcycles
              << " safety=" << p->safety << " " << p->variant << " " << p->scheme;
        if (uses_relaxation(p->scheme))
          title << " relaxation=" << p->relaxation;
        title << " contrast=" << p->contrast;
        o << marker(p->scheme, X(p->result.wall_time_s), Y(ey(p)), p->pareto ? 5 : 3.5,
                    p->pareto ? "#c00" : "#36c", title.str());
      }
    for (const auto *p : front) // label the front
      o << "<text x=\"" << X(p->result.wall_time_s) + 7 << "\" y=\"" << Y(ey(p)) - 5
        << "\" font-size=\"10\" fill=\"#c00\">b/a " << std::setprecision(3)
        << p->region_factor << ", a/d " << p->resolution << ", k " << p->subcycles
        << ", s " << p->safety << ", " << p->scheme << "</text>\n";
    // Legend: colour marks the front, the shape the scheme (one entry per
    // swept scheme, with how many of its runs are plotted).
    const double lx = W - R + 20;
    o << "<circle cx=\"" << lx << "\" cy=\"" << T + 10
      << "\" r=\"5\" fill=\"#c00\"/><text x=\"" << lx + 10 << "\" y=\"" << T + 14
      << "\">Pareto front</text>\n"
      << "<circle cx=\"" << lx << "\" cy=\"" << T + 30
      << "\" r=\"3.5\" fill=\"#36c\"/><text x=\"" << lx + 10 << "\" y=\"" << T + 34
      << "\">stable run</text>\n";
    std::vector<std::string> schemes;
    for (const auto &r : rows)
      if (std::find(schemes.begin(), schemes.end(), r.scheme) == schemes.end())
        schemes.push_back(r.scheme);
    double y = T + 54;
    for (const auto &s : schemes)
      {
        const auto all   = std::count_if(rows.begin(), rows.end(),
                                         [&](const Row &r) { return r.scheme == s; });
        const auto shown = std::count_if(pts.begin(), pts.end(),
                                         [&](const Row *r) { return r->scheme == s; });
        o << marker(s, lx, y - 4, 4.5, "#555", "") << "<text x=\"" << lx + 10 << "\" y=\""
          << y << "\">" << s << ": " << shown << " of " << all << " runs</text>\n";
        y += 20;
      }
    const auto n_bad = rows.size() - pts.size();
    o << "<text x=\"" << W - R + 12 << "\" y=\"" << y + 6 << "\">" << n_bad
      << " unstable, invalid or</text>\n<text x=\"" << W - R + 12 << "\" y=\"" << y + 20
      << "\">unequilibrated run(s)</text>\n<text x=\"" << W - R + 12 << "\" y=\""
      << y + 34 << "\">not plotted (study.csv)</text>\n</svg>\n";
    write_file_atomically(file, o.str());
  }

  std::vector<SeedGroup> seed_groups(const std::vector<Row>       &rows,
                                     const std::vector<Reference> &refs)
  {
    std::map<std::tuple<double, double, std::string, std::string, unsigned int, double,
                        double, double>,
             std::vector<const Row *>>
        by_setting;
    for (const auto &r : rows)
      if (r.breakable && r.status == "stable" && r.equilibrated && r.reference >= 0 &&
          refs[r.reference].usable())
        by_setting[{r.region_factor, r.resolution, r.variant, r.scheme, r.subcycles,
                    r.safety, r.relaxation, r.contrast}]
            .push_back(&r);
    std::vector<SeedGroup> groups;
    for (const auto &[key, runs] : by_setting)
      {
        if (runs.size() < 2)
          continue;
        std::vector<double> dep, rdep, area, rarea, notch, rnotch, t, rt;
        SeedGroup           g;
        g.runs = runs;
        for (const auto *r : runs)
          {
            const auto &f = refs[r->reference].result;
            dep.push_back(r->result.damage_zone_depth);
            rdep.push_back(f.damage_zone_depth);
            area.push_back(r->result.damage.damaged_area);
            rarea.push_back(f.damage.damaged_area);
            notch.push_back(r->result.damage.notch_angle);
            rnotch.push_back(f.damage.notch_angle);
            t.push_back(r->result.wall_time_s);
            rt.push_back(f.wall_time_s);
            g.too_small += r->region_too_small;
          }
        g.depth     = statistics::mean_interval(dep);
        g.ref_depth = statistics::mean_interval(rdep);
        g.area      = statistics::mean_interval(area);
        g.ref_area  = statistics::mean_interval(rarea);
        g.notch     = statistics::mean_interval(notch);
        g.ref_notch = statistics::mean_interval(rnotch);
        g.time      = statistics::mean_interval(t);
        g.ref_time  = statistics::mean_interval(rt);
        groups.push_back(g);
      }
    return groups;
  }

  void write_seed_chart(const std::string &file, const std::vector<SeedGroup> &groups)
  {
    // Two panels sharing x, the mean wall time (log, whole decades, the
    // references' mean time included): the mean damage-zone depth (top) and
    // the mean damaged area (bottom) relative to the references' means [%],
    // each linear and symmetric about zero. A setting agrees when both
    // means lie in the references' intervals (RegionAnswer), so both are
    // shown, each point coloured by its own measure.
    struct Measure
    {
      const char          *name;
      statistics::Interval SeedGroup::*own, SeedGroup::*ref;
    };
    const Measure measures[] = {
        {"damage-zone depth", &SeedGroup::depth, &SeedGroup::ref_depth},
        {"damaged area", &SeedGroup::area, &SeedGroup::ref_area}};
    const double W = 720, L = 80, R = 200, T = 40, P = 280, gap = 50, B = 60;
    const double H  = T + 2 * P + gap + B;
    double       x0 = 1e300, x1 = -1e300, ref_time = 0;
    for (const auto &g : groups)
      {
        x0       = std::min({x0, std::log10(g.time.mean), std::log10(g.ref_time.mean)});
        x1       = std::max({x1, std::log10(g.time.mean), std::log10(g.ref_time.mean)});
        ref_time = std::max(ref_time, g.ref_time.mean);
      }
    if (groups.empty())
      x0 = x1 = 0;
    x0 = std::floor(x0), x1 = std::max(std::ceil(x1), x0 + 1);
    const auto X = [&](double t) {
      return L + (W - L - R) * (std::log10(t) - x0) / (x1 - x0);
    };
    std::ostringstream o; // replaced atomically below
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << L
      << "\" y=\"24\" font-size=\"15\">mean over seeds: wall time versus damage "
         "difference (95 % intervals)</text>\n";
    for (int k = 0; k < 2; ++k)
      {
        const Measure &me  = measures[k];
        const double   top = T + k * (P + gap), bottom = top + P;
        const auto     rel = [&](const SeedGroup &g, double v) {
          return 100 * v / (g.*me.ref).mean;
        };
        double ymax = 10;
        for (const auto &g : groups)
          for (double v : {(g.*me.own).mean - (g.*me.ref).mean + (g.*me.own).half_width,
                           (g.*me.own).mean - (g.*me.ref).mean - (g.*me.own).half_width,
                           (g.*me.ref).half_width})
            if (std::isfinite(rel(g, v)))
              ymax = std::max(ymax, std::abs(rel(g, v)));
        ymax         = 10 * std::ceil(ymax / 10);
        const auto Y = [&](double p) { return top + P * (ymax - p) / (2 * ymax); };
        for (int e = int(x0); e <= int(x1); ++e)
          {
            o << "<line x1=\"" << X(std::pow(10, e)) << "\" y1=\"" << top << "\" x2=\""
              << X(std::pow(10, e)) << "\" y2=\"" << bottom << "\" stroke=\"#ddd\"/>\n";
            if (k == 1)
              o << "<text x=\"" << X(std::pow(10, e)) << "\" y=\"" << bottom + 16
                << "\" text-anchor=\"middle\">1e" << e << "</text>\n";
          }
        for (double p = -ymax; p <= ymax + 1e-9; p += ymax / 4)
          o << "<line x1=\"" << L << "\" y1=\"" << Y(p) << "\" x2=\"" << W - R
            << "\" y2=\"" << Y(p) << "\" stroke=\"" << (p == 0 ? "#888" : "#ddd")
            << "\"/>\n"
            << "<text x=\"" << L - 6 << "\" y=\"" << Y(p) + 4 << "\" text-anchor=\"end\">"
            << p << " %</text>\n";
        // The references' interval, relative to their mean (the widest).
        double band = 0;
        for (const auto &g : groups)
          if (std::isfinite(rel(g, (g.*me.ref).half_width)))
            band = std::max(band, rel(g, (g.*me.ref).half_width));
        o << "<rect x=\"" << L << "\" y=\"" << Y(band) << "\" width=\"" << W - L - R
          << "\" height=\"" << Y(-band) - Y(band)
          << "\" fill=\"#090\" fill-opacity=\"0.12\"/>\n";
        if (ref_time > 0)
          o << "<line x1=\"" << X(ref_time) << "\" y1=\"" << top << "\" x2=\""
            << X(ref_time) << "\" y2=\"" << bottom
            << "\" stroke=\"#090\" stroke-dasharray=\"6,4\"/>\n";
        o << "<rect x=\"" << L << "\" y=\"" << top << "\" width=\"" << W - L - R
          << "\" height=\"" << P << "\" fill=\"none\" stroke=\"black\"/>\n"
          << "<text transform=\"translate(20," << top + P / 2
          << ") rotate(-90)\" text-anchor=\"middle\">" << me.name
          << ": (mean - reference mean) / reference mean</text>\n";
        for (const auto &g : groups)
          {
            const double x = X(g.time.mean),
                         y = rel(g, (g.*me.own).mean - (g.*me.ref).mean),
                         h = rel(g, (g.*me.own).half_width);
            if (!std::isfinite(y))
              continue;
            const bool in = (g.*me.ref).contains((g.*me.own).mean);
            if (std::isfinite(h))
              o << "<line x1=\"" << x << "\" y1=\"" << Y(y + h) << "\" x2=\"" << x
                << "\" y2=\"" << Y(y - h)
                << "\" stroke=\"#36c\" stroke-width=\"1.5\"/>\n";
            const auto *r0 = g.runs.front();
            o << "<circle cx=\"" << x << "\" cy=\"" << Y(y) << "\" r=\"5\" fill=\""
              << (in ? "#090" : "#c00") << "\"><title>b/a=" << r0->region_factor
              << " a/d=" << r0->resolution << " " << r0->variant << " " << r0->scheme
              << ", " << g.runs.size() << " seeds</title></circle>\n"
              << "<text x=\"" << x + 7 << "\" y=\"" << Y(y) - 5
              << "\" font-size=\"10\">b/a " << std::setprecision(3) << r0->region_factor
              << ", a/d " << r0->resolution << "</text>\n";
          }
      }
    o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 20
      << "\" text-anchor=\"middle\">mean wall-clock time [s]</text>\n"
      << "<rect x=\"" << W - R + 14 << "\" y=\"" << T + 4
      << "\" width=\"12\" height=\"12\" fill=\"#090\" fill-opacity=\"0.12\"/>"
      << "<text x=\"" << W - R + 30 << "\" y=\"" << T + 14
      << "\">references' 95 % interval</text>\n"
      << "<line x1=\"" << W - R + 14 << "\" y1=\"" << T + 30 << "\" x2=\"" << W - R + 26
      << "\" y2=\"" << T + 30 << "\" stroke=\"#090\" stroke-dasharray=\"6,4\"/><text x=\""
      << W - R + 30 << "\" y=\"" << T + 34 << "\">references' mean time</text>\n"
      << "<circle cx=\"" << W - R + 20 << "\" cy=\"" << T + 50
      << "\" r=\"5\" fill=\"#090\"/><text x=\"" << W - R + 30 << "\" y=\"" << T + 54
      << "\">mean within it</text>\n"
      << "<circle cx=\"" << W - R + 20 << "\" cy=\"" << T + 70
      << "\" r=\"5\" fill=\"#c00\"/><text x=\"" << W - R + 30 << "\" y=\"" << T + 74
      << "\">mean outside it</text>\n"
      << "<line x1=\"" << W - R + 20 << "\" y1=\"" << T + 84 << "\" x2=\"" << W - R + 20
      << "\" y2=\"" << T + 98 << "\" stroke=\"#36c\" stroke-width=\"1.5\"/><text x=\""
      << W - R + 30 << "\" y=\"" << T + 94 << "\">95 % interval of the mean</text>\n"
      << "</svg>\n";
    write_file_atomically(file, o.str());
  }

  RegionAnswer region_answer(const std::vector<Row>       &rows,
                             const std::vector<Reference> &refs, double tolerance)
  {
    // Per region factor (other settings and seeds pooled): its compared runs
    // and their references. With two seeds or more everywhere, a factor
    // agrees when its mean damage-zone depth and mean damaged area lie in the
    // 95 % confidence intervals of its references' (common/statistics.h);
    // with one seed, when the depth is within the tolerance of the
    // reference's. Either way fewer than half of its runs may be
    // region_too_small. Then walk down from the largest factor: the answer
    // changes below the smallest factor reached before the first
    // disagreement.
    struct Factor
    {
      std::vector<double> depth, area, ref_depth, ref_area;
      std::set<int>       seen; // references counted once
      std::size_t         small = 0;
    };
    std::map<double, Factor, std::greater<double>> by_factor;
    for (const auto &r : rows)
      if (r.breakable && r.status == "stable" && r.equilibrated &&
          std::isfinite(r.error) && r.reference >= 0)
        {
          auto &s = by_factor[r.region_factor];
          s.depth.push_back(r.result.damage_zone_depth);
          s.area.push_back(r.result.damage.damaged_area);
          if (s.seen.insert(r.reference).second)
            {
              s.ref_depth.push_back(refs[r.reference].result.damage_zone_depth);
              s.ref_area.push_back(refs[r.reference].result.damage.damaged_area);
            }
          s.small += r.region_too_small;
        }
    RegionAnswer a;
    a.rule = "confidence";
    for (const auto &[f, s] : by_factor)
      if (s.ref_depth.size() < 2)
        a.rule = "tolerance";
    bool broken = false;
    for (const auto &[f, s] : by_factor)
      {
        const auto depth = statistics::mean_interval(s.depth);
        bool       ok    = 2 * s.small < s.depth.size();
        if (a.rule == "confidence")
          ok = ok && statistics::mean_interval(s.ref_depth).contains(depth.mean) &&
               statistics::mean_interval(s.ref_area)
                   .contains(statistics::mean_interval(s.area).mean);
        else
          {
            const double ref = statistics::mean_interval(s.ref_depth).mean;
            ok               = ok && std::abs(depth.mean - ref) <= tolerance * ref;
          }
        if (!ok && a.largest_disagreeing < 0)
          a.largest_disagreeing = f;
        broken = broken || !ok;
        if (!broken)
          a.smallest_agreeing = f;
      }
    return a;
  }

  std::size_t write_speedup(const std::string &csv, const std::string &markdown,
                            const std::vector<Row>       &rows,
                            const std::vector<Reference> &refs, double tolerance,
                            const RegionAnswer &answer)
  {
    std::ostringstream c, m; // replaced atomically below
    c << "run,region_factor,region_auto,a_over_d,seed,variant,scheme,subcycles,"
         "timestep_safety,relaxation,stiffness_contrast,n_particles,"
         "reference_particles,wall_time_s,reference_wall_time_s,speedup,"
         "damage_zone_depth_m,reference_depth_m,depth_rel_diff,cracks_excavation,"
         "reference_cracks_excavation,region_too_small\n";
    m << "# demfem study: breakable tunnel versus the full-DEM reference\n\n"
      << "Full-DEM references (servo-controlled membrane at the in-situ stress):\n\n"
      << "| a/d | seed | status | grains | steps (+ genesis packing) | wall time [s] | "
         "damage-zone depth [m] "
         "| excavation cracks (tensile/shear) | servo error in situ |\n"
      << "|---|---|---|---|---|---|---|---|---|\n";
    for (const auto &f : refs)
      m << "| " << num(f.resolution) << " | " << f.seed << " | " << f.status << " | "
        << f.result.n_particles << " | " << f.result.steps << " (+ "
        << f.result.genesis_steps << ") | " << num(f.result.wall_time_s) << " | "
        << num(f.result.damage_zone_depth) << " | " << f.cracks_excavation() << " ("
        << f.result.cracks_tensile << "/" << f.result.cracks_shear << " in all) | "
        << num(f.result.servo_error_insitu) << " |\n";
    m << "\nSpeed-up of the embedded model at equal damage-zone depth and damaged area "
         "(both within +-"
      << num(100 * tolerance) << " % of the reference):\n\n"
      << "| run | b/a | a/d | variant, scheme, k, safety | grains (reference) | wall "
         "time "
         "[s] (reference) | speed-up | depth [m] (reference) | excavation cracks "
         "(reference) |\n|---|---|---|---|---|---|---|---|---|\n";
    std::size_t n = 0;
    for (const auto &r : rows)
      {
        if (!(r.breakable && r.status == "stable" && r.equilibrated && r.agrees &&
              r.reference >= 0 && r.result.wall_time_s > 0))
          continue;
        const auto  &f  = refs[r.reference];
        const double sp = f.result.wall_time_s / r.result.wall_time_s;
        c << r.index << "," << num(r.region_factor) << ","
          << (r.region_auto ? "yes" : "no") << "," << num(r.resolution) << "," << r.seed
          << "," << r.variant << "," << r.scheme << "," << r.subcycles << ","
          << num(r.safety) << "," << num(r.relaxation, uses_relaxation(r.scheme)) << ","
          << num(r.contrast) << "," << r.result.n_particles << "," << f.result.n_particles
          << "," << num(r.result.wall_time_s) << "," << num(f.result.wall_time_s) << ","
          << num(sp) << "," << num(r.result.damage_zone_depth) << ","
          << num(f.result.damage_zone_depth) << "," << num(r.error) << ","
          << r.cracks_excavation << "," << f.cracks_excavation() << ","
          << (r.region_too_small ? "yes" : "no") << "\n";
        m << "| " << r.index << " | " << num(r.region_factor)
          << (r.region_auto ? " (auto)" : "") << " | " << num(r.resolution) << " | "
          << r.variant << ", " << r.scheme << ", " << r.subcycles << ", " << num(r.safety)
          << " | " << r.result.n_particles << " (" << f.result.n_particles << ") | "
          << num(r.result.wall_time_s) << " (" << num(f.result.wall_time_s) << ") | "
          << std::setprecision(3) << sp << " | " << num(r.result.damage_zone_depth)
          << " (" << num(f.result.damage_zone_depth) << ") | " << r.cracks_excavation
          << " (" << f.cracks_excavation() << ") |\n";
        ++n;
      }
    if (n == 0)
      m << "| none | | | | | | | | |\n";
    // The damage-zone depth of one packing is noisy (the references of
    // three seeds: 0.42, 0.61, 0.53 m at a/d = 4): with several seeds, the
    // means over the seeds are compared with their confidence intervals,
    // which is what "equal damage" can mean at this resolution.
    const auto groups = seed_groups(rows, refs);
    if (!groups.empty())
      m << "\nMean over packing seeds with 95 % confidence intervals (Student's t; "
           "the embedded runs of each setting and the references of the same "
           "seeds; chart study_seeds.svg). Depth: 90th-percentile distance from "
           "the wall of the cracks connected to it (docs/tunnel.md, \"Damage "
           "measures\"); area: damaged area per unit length; notch: the deepest "
           "sector's angle:\n\n"
           "| b/a | a/d | variant, scheme, k, safety | seeds | depth [m] | reference "
           "depth [m] | damaged area [m2] | reference area [m2] | notch angle [deg] "
           "| reference notch [deg] | within the reference's interval (depth, area) "
           "| wall time [s] (reference) | speed-up | region_too_small |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    const auto ci = [](const statistics::Interval &i) {
      return num(i.mean) + " +- " + num(i.half_width);
    };
    for (const auto &g : groups)
      {
        const auto *r0 = g.runs.front();
        m << "| " << num(r0->region_factor) << (r0->region_auto ? " (auto)" : "") << " | "
          << num(r0->resolution) << " | " << r0->variant << ", " << r0->scheme << ", "
          << r0->subcycles << ", " << num(r0->safety) << " | " << g.runs.size() << " | "
          << ci(g.depth) << " | " << ci(g.ref_depth) << " | " << ci(g.area) << " | "
          << ci(g.ref_area) << " | " << ci(g.notch) << " | " << ci(g.ref_notch) << " | "
          << (g.ref_depth.contains(g.depth.mean) ? "yes" : "no") << ", "
          << (g.ref_area.contains(g.area.mean) ? "yes" : "no") << " | "
          << num(g.time.mean) << " (" << num(g.ref_time.mean) << ") | "
          << num(g.ref_time.mean / g.time.mean) << " | " << g.too_small << " of "
          << g.runs.size() << " |\n";
      }
    m << "\nWhere a smaller region changes the answer: ";
    if (answer.largest_disagreeing < 0)
      m << "no swept region factor disagreed with the reference";
    else
      m << "region factor b/a = " << num(answer.largest_disagreeing)
        << " disagrees with the reference"
        << (answer.rule == "confidence"
                ? " (mean depth or damaged area outside the references' 95 % interval)"
                : " on the damage-zone depth");
    m << "; every swept factor >= "
      << (answer.smallest_agreeing < 0 ? std::string("(none)")
                                       : num(answer.smallest_agreeing))
      << " agrees.\n";
    write_file_atomically(csv, c.str());
    write_file_atomically(markdown, m.str());
    return n;
  }
} // namespace demfem::apps::study
