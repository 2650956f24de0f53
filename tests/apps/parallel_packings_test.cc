// Packings side by side (apps/parallel_packings.h): each worker's share of
// the OpenMP threads, and the shares a finished worker leaves to the
// packing still running.
#include "apps/parallel_packings.h"

#include <catch2/catch.hpp>

#include <omp.h>

#include <array>
#include <atomic>
#include <thread>

using namespace demfem::apps;

TEST_CASE("packings side by side: the last packing takes the threads of finished workers",
          "[calibrate][seeds]")
{
  // Three packings on two threads: two workers, one thread each; the third
  // packing runs on the worker that finished first and, once the other
  // worker has no packing left, takes both threads at its next rebalance.
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  std::atomic<int>   started{0};
  std::array<int, 3> share_first{}, share_last{};
  for_each_packing(3, [&](const int k) {
    if (k < 2)
      {
        // Both first packings running: one thread each, before and after a
        // rebalance (both workers are busy).
        ++started;
        while (started.load() < 2)
          std::this_thread::yield();
        share_first[k] = omp_get_max_threads();
        rebalance_packing_threads();
        share_last[k] = omp_get_max_threads();
        return;
      }
    share_first[k] = omp_get_max_threads();
    while (packing_workers::busy.load() > 1) // the other worker leaves
      std::this_thread::yield();
    rebalance_packing_threads();
    share_last[k] = omp_get_max_threads();
  });
  CHECK(share_first == std::array<int, 3>{1, 1, 1});
  CHECK(share_last == std::array<int, 3>{1, 1, 2});
  // Outside a worker it changes nothing.
  rebalance_packing_threads();
  CHECK(omp_get_max_threads() == 2);
  omp_set_num_threads(saved);
}
