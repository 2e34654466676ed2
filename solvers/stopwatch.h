// Wall time of a computation, for the seconds results report (map grids, fits, sweep speeds) and
// the progress lines of the command line.
#pragma once

#include <chrono>

namespace rubcont {

using SteadyClock = std::chrono::steady_clock;

// Seconds of wall time since `start`.
inline double SecondsSince(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

}  // namespace rubcont
