#pragma once
// Progress line of a laboratory test (phase, step, stress, strain, cracks,
// ETA) on stderr, at most every 0.5 s on a terminal and every 5 s into a
// file: `demfem calibrate` and `demfem tunnel --probe`.
#include "apps/calibrate_output.h"
#include "apps/parallel_packings.h"
#include "dem/specimen/lab_tests.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>

namespace demfem::apps
{
  class LabTestProgress
  {
  public:
    explicit LabTestProgress(std::string test)
        : test_(std::move(test))
        , tty_(isatty(2))
    {
    }
    void operator()(const dem::LabProgress &g)
    {
      rebalance_packing_threads();
      const double t = seconds_since(t0_);
      if (t - last_ < (tty_ ? 0.5 : 5.0))
        return;
      last_ = t;
      std::ostringstream s;
      s.precision(4);
      s << "[" << test_ << "] " << g.phase << " step " << g.step << "  stress "
        << g.stress / 1e6 << " MPa  strain " << g.strain << "  cracks " << g.cracks;
      if (g.fraction_done > 0.01)
        s << "  ETA " << std::lround(t * (1 - g.fraction_done) / g.fraction_done) << " s";
      // One write per line: packings running side by side
      // (apps/parallel_packings.h) print between each other's lines.
      std::cerr << (tty_ ? "\r" + s.str() + "\033[K" : s.str() + "\n") << std::flush;
    }
    ~LabTestProgress()
    {
      if (tty_ && last_ > 0)
        std::cerr << "\n";
    }

  private:
    std::string                           test_;
    bool                                  tty_;
    std::chrono::steady_clock::time_point t0_   = std::chrono::steady_clock::now();
    double                                last_ = 0;
  };

  /// One laboratory test with its progress line under `label` (the
  /// calibration's tests and their rate repeats, the fit's evaluations,
  /// the tunnel probe's packings); `snapshot` as in dem::LabCallbacks.
  template <int dim>
  dem::LabTestResult run_lab_test_with_progress(
      dem::Specimen<dim> &specimen, const dem::LabTestParams &lab,
      const std::string                                                   &label,
      std::function<void(const dem::Specimen<dim> &, const std::string &)> snapshot = {})
  {
    LabTestProgress        progress(label);
    dem::LabCallbacks<dim> cb;
    cb.progress = [&](const dem::LabProgress &g) { progress(g); };
    cb.snapshot = std::move(snapshot);
    return dem::run_lab_test(specimen, lab, cb);
  }
} // namespace demfem::apps
