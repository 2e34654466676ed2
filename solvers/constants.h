// The numbers every folder needs, defined once: π and the quiet NaN that marks "no value" in
// results (a missing peak, a copy that never arrived, a bifurcation not found).
#pragma once

#include <limits>

namespace rubcont {

inline constexpr double kPi = 3.14159265358979323846;     // π, to the last bit of a double
inline constexpr double kTwoPi = 2.0 * kPi;               // 2π = 6.283185307179586
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace rubcont
