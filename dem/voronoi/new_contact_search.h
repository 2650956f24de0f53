#pragma once
// Search for new contacts between Voronoi grains (seed 004 §2: "If a new
// contact between two grains is found to occur, ..."; docs/voronoi.md,
// "New contacts"), shared by the flexible and the rigid model: two grains
// not in contact whose disks overlap (the DEM criterion the seed keeps).
//
// A Verlet list. At a rebuild the current disk centres go into a uniform
// grid of cells no smaller than the largest disk diameter plus the skin,
// so every pair within r_a + r_b + skin lies in the same or adjacent grid
// cells; those pairs not in contact yet are the candidates. Until some disk
// has moved more than half the skin since the rebuild, no other pair can
// come within r_a + r_b (each disk of the pair moved less than skin / 2),
// so each step only tests the candidates: O(N) for the displacement check
// plus O(candidates), no allocation in the steady state. Everything is
// serial and in ascending (a, b) order, so the contacts a model forms from
// the result do not depend on the thread count.
#include <cstdint>
#include <utility>
#include <vector>

namespace demfem::dem::voronoi
{
  /// Squared distance from (px, py) to the segment (ax, ay)-(bx, by): the
  /// "Voronoi edge closest to the contact location" of seed 004 §2, for both
  /// models' formation of a new contact.
  double segment_distance2(double px, double py, double ax, double ay, double bx,
                           double by);

  class NewContactSearch
  {
  public:
    /// Starts over for n grains with no pair in contact.
    void reset(int n);
    /// Records that a and b are in contact (any order); the search never
    /// returns the pair again.
    void add_contact(int a, int b);
    bool in_contact(int a, int b) const;

    /// Rebuilds the candidate list from the disks (x, y, r) of the grains
    /// with active[c] != 0 (grains without a cell have no disk in the
    /// model), skin = skin_fraction times the largest active radius.
    void rebuild(const double *x, const double *y, const double *r, const char *active,
                 double skin_fraction);
    /// True if some active disk moved more than half the skin since the
    /// last rebuild (the candidate list may then miss a pair).
    bool stale(const double *x, const double *y, const char *active) const;

    /// The candidates whose disks overlap at (x, y, r) and that are not in
    /// contact yet, in ascending (a, b) order; they are recorded as in
    /// contact (the caller forms their contacts).
    const std::vector<std::pair<int, int>> &new_overlaps(const double *x, const double *y,
                                                         const double *r);

    /// Candidate pairs (a < b, ascending) of the last rebuild: disks within
    /// r_a + r_b + skin, not in contact then.
    const std::vector<std::pair<int, int>> &candidates() const { return candidate; }
    double                                  skin() const { return skin_; }

  private:
    int                       n = 0;
    std::vector<std::int64_t> keys; ///< a n + b (a < b) of pairs in contact, sorted
    std::vector<std::pair<int, int>> candidate, found;
    std::vector<char>                candidate_done;     ///< formed since the rebuild
    std::vector<double>              verlet_x, verlet_y; ///< disk centres at the rebuild
    std::vector<int>                 grid_start, grid_item, grid_fill;
    double                           skin_ = 0;
  };
} // namespace demfem::dem::voronoi
