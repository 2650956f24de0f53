// Output helpers of `demfem calibrate` (see calibrate_output.h).
#include "apps/calibrate_output.h"

#include "apps/calibrate.h"
#include "dem/io/json_number.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace demfem::apps
{
  double post_peak_strain_ratio(const std::vector<double> &strain,
                                const std::vector<double> &stress, double fraction)
  {
    std::size_t peak = 0;
    for (std::size_t i = 0; i < stress.size(); ++i)
      if (std::abs(stress[i]) > std::abs(stress[peak]))
        peak = i;
    const double s_peak = std::abs(stress.empty() ? 0.0 : stress[peak]);
    const double e_peak = std::abs(stress.empty() ? 0.0 : strain[peak]);
    for (std::size_t i = peak + 1; i < stress.size(); ++i)
      if (std::abs(stress[i]) < fraction * s_peak && e_peak > 0)
        return (std::abs(strain[i]) - e_peak) / e_peak;
    return std::numeric_limits<double>::quiet_NaN();
  }

  namespace
  {
    std::string xml(const std::string &s)
    {
      std::string o;
      for (char c : s)
        if (c == '<')
          o += "&lt;";
        else if (c == '>')
          o += "&gt;";
        else if (c == '&')
          o += "&amp;";
        else
          o += c;
      return o;
    }

    // "Nice" tick step (1, 2, 5 x 10^k) giving about n intervals.
    double tick_step(double range, int n)
    {
      if (!(range > 0))
        return 1;
      const double raw = range / n, p = std::pow(10.0, std::floor(std::log10(raw)));
      for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw)
          return m * p;
      return 10 * p;
    }
  } // namespace

  Json &Json::num(const std::string &key, double v)
  {
    j_[key] = dem::json_number(v);
    return *this;
  }
  Json &Json::str(const std::string &key, const std::string &v)
  {
    j_[key] = v;
    return *this;
  }
  Json &Json::obj(const std::string &key, const Json &v)
  {
    j_[key] = v.j_;
    return *this;
  }
  Json &Json::nums(const std::string &key, const std::vector<double> &v)
  {
    auto a = nlohmann::ordered_json::array();
    for (double x : v)
      a.push_back(dem::json_number(x));
    j_[key] = a;
    return *this;
  }
  Json &Json::objs(const std::string &key, const std::vector<Json> &v)
  {
    auto a = nlohmann::ordered_json::array();
    for (const auto &x : v)
      a.push_back(x.j_);
    j_[key] = a;
    return *this;
  }
  std::string Json::text() const { return j_.dump(2); }

  std::string Json::csv(const std::vector<Json> &rows, const Json &header)
  {
    std::ostringstream s;
    s << std::setprecision(17);
    const auto scalar = [&s](const nlohmann::ordered_json &v) {
      if (v.is_null())
        s << "nan";
      else if (v.is_string())
        s << v.get<std::string>();
      else
        s << v.get<double>();
    };
    const auto cell = [&](const nlohmann::ordered_json &v) {
      if (!v.is_array())
        return scalar(v);
      for (std::size_t k = 0; k < v.size(); ++k) // space-separated
        {
          if (k)
            s << ' ';
          scalar(v[k]);
        }
    };
    std::vector<std::string> keys;
    for (const auto &item : header.j_.items())
      s << (keys.empty() ? "" : ",") << item.key(), keys.push_back(item.key());
    s << '\n';
    for (const auto &r : rows)
      {
        std::size_t k = 0;
        for (const auto &item : r.j_.items())
          {
            if (k >= keys.size() || item.key() != keys[k])
              throw std::logic_error("Json::csv: a row's keys differ from the header's");
            if (k++)
              s << ',';
            cell(item.value());
          }
        if (k != keys.size())
          throw std::logic_error("Json::csv: a row's keys differ from the header's");
        s << '\n';
      }
    return s.str();
  }

  std::string history_csv(const std::vector<dem::HistoryRow> &h)
  {
    std::ostringstream s;
    s << "step,time_s,axial_strain,lateral_strain,gauge_axial_strain,volumetric_strain,"
         "axial_stress_Pa,region_axial_stress_Pa,region_lateral_stress_Pa,axial_force_N,"
         "load,cracks_tension,cracks_shear,lateral_wall_stress_Pa\n";
    s << std::setprecision(10);
    for (const auto &r : h)
      s << r.step << ',' << r.time << ',' << r.axial_strain << ',' << r.lateral_strain
        << ',' << r.gauge_axial_strain << ',' << r.volumetric_strain << ','
        << r.axial_stress << ',' << r.region_axial_stress << ','
        << r.region_lateral_stress << ',' << r.axial_force << ',' << r.load << ','
        << r.cracks_tension << ',' << r.cracks_shear << ',' << r.lateral_wall_stress
        << '\n';
    return s.str();
  }

  std::string compression_strains_svg(const dem::LabTestResult &r, const int dim,
                                      const std::string &title)
  {
    // The figure of Martin & Chandler (1994): the crack volumetric strain is
    // the volumetric strain less its elastic part (1 - k nu) d sigma_a / E
    // of the loading branch's E, nu (k lateral directions; 2D: the
    // plane-stress pair the test measured), here without the fit window's
    // offset the reading removes (dem/specimen/crack_initiation.h).
    const auto &H = r.history;
    if (H.empty() || r.peak_row >= H.size())
      return svg_plot(title, "strain [%]", "axial stress [MPa]", {});
    const double E = dim == 3 ? r.E : r.E_ps, nu = dim == 3 ? r.nu : r.nu_ps;
    PlotSeries   axial{"axial", {}, {}, "#000"}, lateral{"lateral", {}, {}, "#06c"},
        volumetric{"volumetric", {}, {}, "#c00"},
        crack{"crack volumetric", {}, {}, "#e80"};
    for (std::size_t i = 0; i <= r.peak_row; ++i)
      {
        const auto  &h  = H[i];
        const double y  = -h.axial_stress / 1e6;
        const double cv = (h.volumetric_strain - H[0].volumetric_strain) -
                          (1 - (dim - 1) * nu) * (h.axial_stress - H[0].axial_stress) / E;
        axial.x.push_back(-100 * (h.gauge_axial_strain - H[0].gauge_axial_strain));
        lateral.x.push_back(-100 * (h.lateral_strain - H[0].lateral_strain));
        volumetric.x.push_back(-100 * (h.volumetric_strain - H[0].volumetric_strain));
        crack.x.push_back(E > 0 ? -100 * cv : std::numeric_limits<double>::quiet_NaN());
        for (PlotSeries *p : {&axial, &lateral, &volumetric, &crack})
          p->y.push_back(y);
      }
    double x0 = 0, x1 = 0;
    for (const PlotSeries *p : {&axial, &lateral, &volumetric, &crack})
      for (const double x : p->x)
        if (std::isfinite(x))
          x0 = std::min(x0, x), x1 = std::max(x1, x);
    std::vector<PlotSeries> all{axial, lateral, volumetric, crack};
    // Each reading in the colour of the curve it is read from.
    auto level = [&](const char *what, double stress, const char *colour) {
      if (!std::isfinite(stress))
        return;
      std::ostringstream label;
      label << what << " " << std::fixed << std::setprecision(2) << stress / r.peak
            << " of the peak";
      all.push_back({label.str(), {x0, x1}, {stress / 1e6, stress / 1e6}, colour});
    };
    level("crack initiation, crack volumetric strain:", r.crack_initiation_volumetric,
          "#e80");
    level("crack initiation, lateral strain response:", r.crack_initiation_lateral,
          "#06c");
    level("crack initiation, crack count:", r.crack_initiation_count, "#999");
    level("crack damage, volumetric reversal:", r.crack_damage, "#c00");
    // Headroom above the peak for the legend (an invisible line).
    all.push_back({"", {x0, x0}, {0, 1.7 * r.peak / 1e6}, "none"});
    return svg_plot(title, "strain, compression positive [%]", "axial stress [MPa]", all);
  }

  std::string svg_plot(const std::string &title, const std::string &xlabel,
                       const std::string &ylabel, const std::vector<double> &x,
                       const std::vector<double> &y)
  {
    return svg_plot(title, xlabel, ylabel, {PlotSeries{"", x, y}});
  }

  std::string svg_plot(const std::string &title, const std::string &xlabel,
                       const std::string &ylabel, const std::vector<PlotSeries> &series)
  {
    const double W = 640, Hh = 440, l = 80, r = 20, t = 40, b = 60;
    double       x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    for (const auto &d : series)
      for (std::size_t i = 0; i < d.x.size() && i < d.y.size(); ++i)
        if (std::isfinite(d.x[i]) && std::isfinite(d.y[i]))
          x0 = std::min(x0, d.x[i]), x1 = std::max(x1, d.x[i]), y0 = std::min(y0, d.y[i]),
          y1 = std::max(y1, d.y[i]);
    const double dx = tick_step(x1 - x0, 6), dy = tick_step(y1 - y0, 6);
    x0 = std::floor(x0 / dx) * dx, x1 = std::ceil(x1 / dx) * dx;
    y0 = std::floor(y0 / dy) * dy, y1 = std::ceil(y1 / dy) * dy;
    if (x1 <= x0)
      x1 = x0 + 1;
    if (y1 <= y0)
      y1 = y0 + 1;
    auto X = [&](double v) { return l + (v - x0) / (x1 - x0) * (W - l - r); };
    auto Y = [&](double v) { return Hh - b - (v - y0) / (y1 - y0) * (Hh - t - b); };
    std::ostringstream s;
    s << std::setprecision(6);
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << Hh
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << W / 2 << "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">"
      << xml(title) << "</text>\n";
    for (double v = x0; v <= x1 + 0.5 * dx; v += dx)
      s << "<line x1=\"" << X(v) << "\" y1=\"" << t << "\" x2=\"" << X(v) << "\" y2=\""
        << Hh - b << "\" stroke=\"#ddd\"/>\n<text x=\"" << X(v) << "\" y=\""
        << Hh - b + 16 << "\" text-anchor=\"middle\">"
        << (std::abs(v) < 1e-12 * dx ? 0.0 : v) << "</text>\n";
    for (double v = y0; v <= y1 + 0.5 * dy; v += dy)
      s << "<line x1=\"" << l << "\" y1=\"" << Y(v) << "\" x2=\"" << W - r << "\" y2=\""
        << Y(v) << "\" stroke=\"#ddd\"/>\n<text x=\"" << l - 6 << "\" y=\"" << Y(v) + 4
        << "\" text-anchor=\"end\">" << (std::abs(v) < 1e-12 * dy ? 0.0 : v)
        << "</text>\n";
    s << "<rect x=\"" << l << "\" y=\"" << t << "\" width=\"" << W - l - r
      << "\" height=\"" << Hh - t - b << "\" fill=\"none\" stroke=\"black\"/>\n";
    int legend = 0;
    for (const auto &d : series)
      {
        if (d.markers)
          {
            for (std::size_t i = 0; i < d.x.size() && i < d.y.size(); ++i)
              if (std::isfinite(d.x[i]) && std::isfinite(d.y[i]))
                s << "<circle cx=\"" << X(d.x[i]) << "\" cy=\"" << Y(d.y[i])
                  << "\" r=\"4\" fill=\"" << d.colour << "\"/>\n";
          }
        else
          {
            s << "<polyline fill=\"none\" stroke=\"" << d.colour
              << "\" stroke-width=\"1.5\" points=\"";
            for (std::size_t i = 0; i < d.x.size() && i < d.y.size(); ++i)
              if (std::isfinite(d.x[i]) && std::isfinite(d.y[i]))
                s << X(d.x[i]) << ',' << Y(d.y[i]) << ' ';
            s << "\"/>\n";
          }
        if (d.label.empty())
          continue;
        const double ly = t + 16 + 16 * legend++;
        if (d.markers)
          s << "<circle cx=\"" << l + 16 << "\" cy=\"" << ly - 4 << "\" r=\"4\" fill=\""
            << d.colour << "\"/>\n";
        else
          s << "<line x1=\"" << l + 8 << "\" y1=\"" << ly - 4 << "\" x2=\"" << l + 24
            << "\" y2=\"" << ly - 4 << "\" stroke=\"" << d.colour
            << "\" stroke-width=\"1.5\"/>\n";
        s << "<text x=\"" << l + 30 << "\" y=\"" << ly << "\">" << xml(d.label)
          << "</text>\n";
      }
    s << "<text x=\"" << (l + W - r) / 2 << "\" y=\"" << Hh - 18
      << "\" text-anchor=\"middle\">" << xml(xlabel) << "</text>\n"
      << "<text transform=\"translate(20," << (t + Hh - b) / 2
      << ") rotate(-90)\" text-anchor=\"middle\">" << xml(ylabel) << "</text>\n</svg>\n";
    return s.str();
  }

  std::string calibration_status(const std::size_t n_at_step_limit,
                                 const std::size_t n_not_split,
                                 const std::size_t n_not_held)
  {
    if (n_at_step_limit > 0)
      return "step_limit_reached";
    if (n_not_split > 0)
      return "brazilian_not_split";
    return n_not_held > 0 ? "confinement_not_held" : "ok";
  }

  CalibrateOutcome calibration_outcome(const std::string &out, const double wall_s,
                                       const std::size_t n_at_step_limit,
                                       const std::size_t n_not_split,
                                       const std::size_t n_not_held)
  {
    std::cerr << "demfem calibrate: wrote " << out << "/material.json (" << wall_s
              << " s)\n";
    const std::string status =
        calibration_status(n_at_step_limit, n_not_split, n_not_held);
    if (status == "ok")
      return {};
    if (n_at_step_limit > 0)
      std::cerr << "demfem calibrate: " << n_at_step_limit
                << " test(s) ended at the step limit\n";
    if (n_not_split > 0)
      std::cerr << "demfem calibrate: " << n_not_split
                << " Brazilian test(s) did not split along the loaded diameter: no "
                   "BTS\n";
    if (n_not_held > 0)
      std::cerr
          << "demfem calibrate: " << n_not_held
          << " confined test(s) did not hold P_c within Tests/confining tolerance\n";
    std::cerr << "demfem calibrate: summary.json: status " << status << "; exit 3\n";
    return {3, status};
  }
  void StrengthEnvelope::fit(const std::string &where)
  {
    const std::string what = where + ": Tests/confining pressures";
    mc                     = dem::fit_mohr_coulomb(sigma_3, sigma_1, what);
    hb                     = dem::fit_hoek_brown(sigma_3, sigma_1, what);
  }

  Json StrengthEnvelope::json() const
  {
    Json m, h, e;
    m.num("cohesion_Pa", mc.cohesion)
        .num("friction_angle_deg", mc.friction_angle * 180 / M_PI)
        .num("sigma_c_Pa", mc.sigma_c)
        .num("slope_q", mc.q)
        .num("r2", mc.r2);
    h.num("sigma_ci_Pa", hb.sigma_ci).num("mi", hb.mi).num("r2", hb.r2);
    e.nums("confining_pressures_Pa", sigma_3)
        .nums("peak_axial_stresses_Pa", sigma_1)
        .obj("mohr_coulomb", m)
        .obj("hoek_brown", h)
        .str("hoek_brown_fit", "linear regression of (sigma_1 - sigma_3)^2 on sigma_3 "
                               "(Hoek & Brown 1997), intact rock s = 1, a = 0.5");
    return e;
  }

  std::string StrengthEnvelope::svg(int dim, const std::vector<PlotSeries> &extra) const
  {
    const double hi = *std::max_element(sigma_3.begin(), sigma_3.end());
    PlotSeries   pts{"peaks", {}, {}, "#000", true};
    PlotSeries   m{"Mohr-Coulomb", {}, {}, "#c00"}, h{"Hoek-Brown", {}, {}, "#06c"};
    for (std::size_t k = 0; k < sigma_3.size(); ++k)
      pts.x.push_back(sigma_3[k] / 1e6), pts.y.push_back(sigma_1[k] / 1e6);
    for (int k = 0; k <= 50; ++k)
      {
        const double s3 = hi * k / 50;
        m.x.push_back(s3 / 1e6), m.y.push_back(dem::mohr_coulomb_sigma_1(mc, s3) / 1e6);
        h.x.push_back(s3 / 1e6), h.y.push_back(dem::hoek_brown_sigma_1(hb, s3) / 1e6);
      }
    std::vector<PlotSeries> all = extra;
    all.insert(all.end(), {m, h, pts});
    std::ostringstream t;
    t.precision(3);
    t << "Triaxial envelope (" << dim << "D): c " << mc.cohesion / 1e6 << " MPa, phi "
      << mc.friction_angle * 180 / M_PI << " deg; m_i " << hb.mi;
    return svg_plot(t.str(), "sigma_3 = Pc  [MPa]", "peak sigma_1  [MPa]", all);
  }
} // namespace demfem::apps
