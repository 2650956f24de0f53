#pragma once
// The post-peak end of a lab test (fistPkg Tables 10-12, load factor;
// docs/calibrate.md, "Lab tests"): shared by the bonded-particle tests
// (dem/specimen/lab_tests.cc) and the Voronoi-grain ones
// (dem/voronoi/voronoi_lab_test.cc), fed every loading step.
#include <cmath>
#include <cstddef>

namespace demfem::dem
{
  /// A test has failed when its load, averaged over a window of physical
  /// time (against platen chatter), is below `load_fraction` x the
  /// reference peak (the largest window mean), cracks formed after that
  /// peak, and the test has cracked at least `failure_cracks` contacts in
  /// all (a failure crosses the specimen; counted in all because a split
  /// that formed mostly before the peak may need only a few more cracks to
  /// open).
  ///
  /// The window is a time, not a number of steps or history rows, so where
  /// a test ends depends neither on `Tests/history interval` nor (beyond
  /// one step) on the time step. The callers take it as the round trip of
  /// a compression wave along the loaded length, 2 L / c: the period of the
  /// specimen's axial ringing between the platens, which a window of that
  /// length averages out.
  ///
  /// A drop below the fraction with no crack since the peak is no failure: a
  /// bonded specimen fails by breaking bonds. It is a disk settling between
  /// the platens or the platens' start-up spike decaying (measured: a 3D
  /// Brazilian disk peaked at 690 N, 5 % of its strength, with no crack,
  /// fell to 91 N, and was ended when 3 contacts cracked under the platens
  /// at 458 N). Such a drop restarts the reference peak at the current
  /// window mean; the test's strength is still its largest load of any
  /// step, kept by the caller.
  class PostPeakEnd
  {
  public:
    /// `window` [s] >= 0; 0 makes every step its own window.
    PostPeakEnd(double load_fraction, std::size_t failure_cracks, double window)
        : load_fraction_(load_fraction)
        , failure_cracks_(failure_cracks)
        , window_(window)
        , window_end_(window)
    {
    }

    /// Adds one loading step of length `dt` [s] at `load`. True when the
    /// step closes a window: the caller then counts the cracks and asks
    /// failed(cracks), so cracks are counted once per window, not per step.
    bool add_step(double dt, double load)
    {
      load_time_ += load * dt;
      elapsed_ += dt;
      time_ += dt;
      if (time_ < window_end_)
        return false;
      window_mean_ = elapsed_ > 0 ? load_time_ / elapsed_ : load;
      load_time_   = 0;
      elapsed_     = 0;
      // Windows end at multiples of the window length from the start, so
      // they do not drift by up to a step each.
      if (window_ > 0)
        window_end_ = (std::floor(time_ / window_) + 1) * window_;
      return true;
    }

    /// Judges the window add_step() has just closed, with the cracks so far.
    /// True when the test has failed.
    bool failed(std::size_t cracks)
    {
      const double load = window_mean_;
      if (load > reference_peak_)
        {
          reference_peak_ = load;
          cracks_at_peak_ = cracks;
          return false;
        }
      if (!(reference_peak_ > 0) || !(load < load_fraction_ * reference_peak_))
        return false;
      if (cracks > cracks_at_peak_)
        return cracks >= failure_cracks_;
      reference_peak_ = load;
      cracks_at_peak_ = cracks;
      ++restarts_;
      return false;
    }

    /// The largest window mean the drop is measured from (progress reports).
    double reference_peak() const { return reference_peak_; }

    /// Drops without cracks that restarted the reference peak.
    std::size_t restarts() const { return restarts_; }

  private:
    double      load_fraction_;
    std::size_t failure_cracks_;
    double      window_;
    double      reference_peak_ = -HUGE_VAL;
    std::size_t cracks_at_peak_ = 0;
    std::size_t restarts_       = 0;
    double      load_time_      = 0; // integral of the load over the open window
    double      elapsed_        = 0; // time in the open window
    double      time_           = 0; // since the first step
    double      window_end_     = 0; // time at which the open window closes
    double      window_mean_    = 0;
  };
} // namespace demfem::dem
