#include "solvers/parallel.h"

#include <atomic>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

TEST_CASE("ParallelFor runs every index exactly once over the threads", "[solvers][parallel]") {
  for (int threads : {1, 3, 64}) {
    std::vector<std::atomic<int>> runs(101);
    ParallelFor(101, threads, [&](int i) { ++runs[static_cast<size_t>(i)]; });
    for (const std::atomic<int>& r : runs) CHECK(r.load() == 1);
  }
  ParallelFor(0, 4, [](int) { FAIL("no job for n = 0"); });
}

TEST_CASE("ParallelFor rethrows a job's exception after every thread stopped", "[solvers][parallel][failure]") {
  std::atomic<int> ran{0};
  CHECK_THROWS_WITH(ParallelFor(50, 2,
                                [&](int i) {
                                  ++ran;
                                  if (i == 7) throw std::runtime_error("job 7 failed");
                                }),
                    "job 7 failed");
  CHECK(ran.load() >= 8);
}

TEST_CASE("ThreadsFor: a positive request as given, 0 one per core", "[solvers][parallel]") {
  CHECK(ThreadsFor(3) == 3);
  CHECK(ThreadsFor(0) >= 1);
}

}  // namespace
}  // namespace rubcont
