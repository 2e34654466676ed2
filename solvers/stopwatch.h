// Wall time of a computation, for the seconds results report (map grids, fits, sweep speeds) and
// the progress lines of the command line.
#pragma once

#include <chrono>
#include <ctime>

namespace rubcont {

using SteadyClock = std::chrono::steady_clock;

// Seconds of wall time since `start`.
inline double SecondsSince(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

// CPU seconds of this process (all threads) since it started: the steadier figure on shared cores.
inline double ProcessCpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }
inline double CpuSecondsSince(double start) { return ProcessCpuSeconds() - start; }

}  // namespace rubcont
