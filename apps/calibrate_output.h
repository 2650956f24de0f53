#pragma once
// Output helpers of `demfem calibrate`: JSON objects built in order
// (nlohmann-json underneath; non-finite numbers become null), the history
// CSV and dependency-free SVG plots (stress-strain curve, strength envelope).
#include "dem/specimen/envelope.h"
#include "dem/specimen/lab_tests.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace demfem::apps
{
  /// Wall time since t0 [s].
  inline double seconds_since(std::chrono::steady_clock::time_point t0)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  /// A test label as a file-name part ("triaxial 5 MPa" -> "triaxial_5_MPa").
  inline std::string file_name(const std::string &label)
  {
    std::string s = label;
    for (auto &c : s)
      if (c == ' ')
        c = '_';
    return s;
  }

  /// Post-peak brittleness of a compression test (docs/calibrate.md,
  /// "Outputs"): the axial strain from the peak of |stress| to the first
  /// later row where |stress| falls below `fraction` of the peak, over the
  /// strain at the peak (both magnitudes). Small: brittle (a sudden drop);
  /// NaN when the curve never falls that far.
  double post_peak_strain_ratio(const std::vector<double> &strain,
                                const std::vector<double> &stress, double fraction = 0.9);

  /// Flat-or-nested JSON object built in order of insertion.
  class Json
  {
  public:
    Json &num(const std::string &key, double v); ///< null if not finite
    Json &str(const std::string &key, const std::string &v);
    Json &obj(const std::string &key, const Json &v);
    /// Array of numbers (non-finite ones null) or of objects.
    Json       &nums(const std::string &key, const std::vector<double> &v);
    Json       &objs(const std::string &key, const std::vector<Json> &v);
    std::string text() const; ///< indented by two spaces
    /// The object itself (to merge into another document without a text
    /// round trip).
    const nlohmann::ordered_json &value() const { return j_; }
    /// The objects as CSV rows under a header of `header`'s keys (a record
    /// of the same kind, so that a table without rows keeps its header):
    /// numbers to 17 digits, null as nan, arrays space-separated. One record
    /// then feeds both a CSV and a JSON output. Throws if a row's keys differ.
    static std::string csv(const std::vector<Json> &rows, const Json &header);

  private:
    nlohmann::ordered_json j_ = nlohmann::ordered_json::object();
  };

  /// history_<test>.csv: one row per recorded step (header names with units).
  std::string history_csv(const std::vector<dem::HistoryRow> &h);

  /// One data set of an SVG plot: a line, or markers only.
  struct PlotSeries
  {
    std::string         label; ///< legend entry (none if empty)
    std::vector<double> x, y;
    std::string         colour  = "#c00";
    bool                markers = false; ///< circles at the points, no line
  };

  /// SVG plot of several series with axes, ticks, labels and a legend.
  std::string svg_plot(const std::string &title, const std::string &xlabel,
                       const std::string &ylabel, const std::vector<PlotSeries> &series);

  /// <test>_strains.svg of a compression test: the axial stress against the
  /// axial, lateral, volumetric and crack volumetric gauge strains up to the
  /// peak (compression positive, from the start of loading), with the crack
  /// initiation by its three readings and the crack damage as horizontal
  /// lines (docs/calibrate.md, "Crack initiation and crack damage").
  std::string compression_strains_svg(const dem::LabTestResult &r, int dim,
                                      const std::string &title);

  /// SVG line plot of y(x) with axes, ticks and labels.
  std::string svg_plot(const std::string &title, const std::string &xlabel,
                       const std::string &ylabel, const std::vector<double> &x,
                       const std::vector<double> &y);
  /// Peaks of a triaxial series and their envelopes (dem/specimen/envelope.h;
  /// docs/calibrate.md, "Triaxial series and envelope"). Compression
  /// positive.
  struct StrengthEnvelope
  {
    std::vector<double> sigma_3, sigma_1; ///< Pc and peak axial stress [Pa]
    dem::MohrCoulombFit mc;
    dem::HoekBrownFit   hb;

    /// Fits both envelopes; `where` names the file in an error.
    void fit(const std::string &where);
    /// material.json's "envelope" object.
    Json json() const;
    /// sigma_1 against sigma_3 in MPa: the peaks, both fitted envelopes and
    /// `extra` series (e.g. each packing's peaks behind their means).
    std::string svg(int dim, const std::vector<PlotSeries> &extra = {}) const;
  };
} // namespace demfem::apps
