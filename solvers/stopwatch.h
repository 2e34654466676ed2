// Wall and CPU time of a computation, for the seconds results report (map grids, fits, sweep
// speeds, ensemble copies), the progress lines of the command line and the benchmarks.
#pragma once

#include <time.h>

#include <chrono>

namespace rubcont {

using SteadyClock = std::chrono::steady_clock;

// Seconds of wall time since `start`.
inline double SecondsSince(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

// CPU seconds (user + system) of this process, all its threads, and of the calling thread: the
// steadier figures on shared cores. Differences of them time a computation.
inline double CpuSecondsOf(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
inline double ProcessCpuSeconds() { return CpuSecondsOf(CLOCK_PROCESS_CPUTIME_ID); }
inline double ThreadCpuSeconds() { return CpuSecondsOf(CLOCK_THREAD_CPUTIME_ID); }
inline double CpuSecondsSince(double start) { return ProcessCpuSeconds() - start; }

}  // namespace rubcont
