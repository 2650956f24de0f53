#pragma once
// The post-peak end of a lab test (fistPkg Tables 10-12, load factor;
// docs/calibrate.md, "Lab tests"): shared by the bonded-particle tests
// (dem/specimen/lab_tests.cc) and the Voronoi-grain ones
// (dem/voronoi/voronoi_lab_test.cc), called once per history row.
#include <array>
#include <cmath>
#include <cstddef>

namespace demfem::dem
{
  /// A test has failed when its load, averaged over the last three history
  /// rows (against platen chatter), is below `load_fraction` x the reference
  /// peak, cracks formed after that peak, and the test has cracked at least
  /// `failure_cracks` contacts in all (a failure crosses the specimen; counted
  /// in all because a split that formed mostly before the peak may need only
  /// a few more cracks to open).
  ///
  /// A drop below the fraction with no crack since the peak is no failure: a
  /// bonded specimen fails by breaking bonds. It is a disk settling between
  /// the platens or the platens' start-up spike decaying (measured: a 3D
  /// Brazilian disk peaked at 690 N, 5 % of its strength, with no crack,
  /// fell to 91 N, and was ended when 3 contacts cracked under the platens
  /// at 458 N). Such a drop restarts the reference peak at the current load;
  /// the test's strength is still its largest load, kept by the caller.
  class PostPeakEnd
  {
  public:
    PostPeakEnd(double load_fraction, std::size_t failure_cracks)
        : load_fraction_(load_fraction)
        , failure_cracks_(failure_cracks)
    {
    }

    /// One history row: its load and the cracks so far. True when the test
    /// has failed.
    bool failed(double load, std::size_t cracks)
    {
      // The mean of the last three rows' loads (the current load until
      // there are three) filters platen chatter.
      last_loads_[rows_ % last_loads_.size()] = load;
      ++rows_;
      const double recent_load =
          rows_ < last_loads_.size()
              ? load
              : (last_loads_[0] + last_loads_[1] + last_loads_[2]) / last_loads_.size();
      if (load > reference_peak_)
        {
          // A new peak is no drop (the three-row mean may lag behind a
          // steep rise).
          reference_peak_ = load;
          cracks_at_peak_ = cracks;
          return false;
        }
      if (!(reference_peak_ > 0) || !(recent_load < load_fraction_ * reference_peak_))
        return false;
      if (cracks > cracks_at_peak_)
        return cracks >= failure_cracks_;
      reference_peak_ = load;
      cracks_at_peak_ = cracks;
      ++restarts_;
      return false;
    }

    /// The peak the drop is measured from (progress reports).
    double reference_peak() const { return reference_peak_; }

    /// Drops without cracks that restarted the reference peak.
    std::size_t restarts() const { return restarts_; }

  private:
    double                load_fraction_;
    std::size_t           failure_cracks_;
    double                reference_peak_ = -HUGE_VAL;
    std::size_t           cracks_at_peak_ = 0;
    std::size_t           restarts_       = 0;
    std::array<double, 3> last_loads_{};
    std::size_t           rows_ = 0;
  };
} // namespace demfem::dem
