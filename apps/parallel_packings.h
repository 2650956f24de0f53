#pragma once
// Packings of one material measured side by side: `demfem calibrate` with
// Problem/seeds and each evaluation of `--fit` run their packings on
// separate threads, one OpenMP thread each, instead of one after the other
// on all threads. A 1 000-grain 2D specimen keeps two threads only partly
// busy (the 2D example: 12.5 minutes a packing on two threads, about 17 on
// one), so two packings at a time finish the six of the example about 1.4
// times sooner. Each packing's results are those of a sequential run bit
// for bit: the contact loop's results do not depend on the thread count
// (docs/architecture.md, "Threads") and the packings share nothing but the
// HDF5 library, which dem/io/checkpoint.cc serializes. Once a worker has
// no packing left, the packings still running take over its threads at
// their next progress report (rebalance_packing_threads): three packings
// on two threads no longer leave a core idle while the third runs alone.
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace demfem::apps
{
  namespace packing_workers
  {
    /// Threads shared out and workers that still have a packing (running
    /// or to come); set by for_each_packing.
    inline std::atomic<int> threads{1}, busy{0};
    /// Whether the calling thread is one of for_each_packing's workers.
    inline thread_local bool on_worker = false;
  } // namespace packing_workers

  /// On a packing worker (for_each_packing): sets this thread's OpenMP
  /// threads to its share of those the busy workers hold, so that a packing
  /// left running alone takes the threads of the workers that finished.
  /// Called between steps from the packing's own thread (the lab tests'
  /// progress, apps/lab_progress.h); the results do not depend on it (the
  /// contact loop's results do not depend on the thread count). Elsewhere
  /// it does nothing.
  inline void rebalance_packing_threads()
  {
    if (!packing_workers::on_worker)
      return;
    const int share = std::max(1, packing_workers::threads.load() /
                                      std::max(1, packing_workers::busy.load()));
    if (share != omp_get_max_threads())
      omp_set_num_threads(share);
  }

  /// How many packings run at a time: one per OpenMP thread, at most n.
  inline int packings_at_a_time(const int n)
  {
    return std::max(1, std::min(n, omp_get_max_threads()));
  }

  /// Calls f(k) for k = 0 .. n-1 on packings_at_a_time(n) threads, each
  /// with its share of the OpenMP threads (the rest of omp_get_max_threads()
  /// / workers goes unused), and the shares of finished workers to the
  /// packings still running (rebalance_packing_threads). After an exception no further k
  /// starts (as in a loop), and the first one by k is rethrown once the running calls
  /// have ended. f must not share mutable state between k.
  template <class F>
  void for_each_packing(const int n, F &&f)
  {
    const int workers = packings_at_a_time(n);
    if (workers <= 1)
      {
        for (int k = 0; k < n; ++k)
          f(k);
        return;
      }
    const int omp_each = std::max(1, omp_get_max_threads() / workers);
    std::vector<std::exception_ptr> errors(n);
    std::atomic<int>                next{0};
    std::atomic<bool>               failed{false};
    std::vector<std::thread>        pool;
    packing_workers::threads = omp_get_max_threads();
    packing_workers::busy    = workers;
    for (int w = 0; w < workers; ++w)
      pool.emplace_back([&] {
        omp_set_num_threads(omp_each);
        packing_workers::on_worker = true;
        for (int k = next++; k < n && !failed; k = next++)
          try
            {
              f(k);
            }
          catch (...)
            {
              errors[k] = std::current_exception();
              failed    = true;
            }
        --packing_workers::busy; // its threads go to the packings still running
      });
    for (auto &t : pool)
      t.join();
    for (const auto &e : errors)
      if (e)
        std::rethrow_exception(e);
  }
} // namespace demfem::apps
