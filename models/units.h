// Units at the edges: scenes and results give running speed in rpm and frequencies in Hz, the
// models take rad/s. Every conversion goes through these functions.
#pragma once

#include "solvers/constants.h"

namespace rubcont {

inline constexpr double kRadPerSecondPerRpm = kTwoPi / 60.0;    // 1 rpm = 2π/60 rad/s
inline constexpr double kRpmPerRadPerSecond = 60.0 / kTwoPi;

constexpr double RpmToRadPerSecond(double rpm) { return rpm * kRadPerSecondPerRpm; }
constexpr double RadPerSecondToRpm(double omega) { return omega * kRpmPerRadPerSecond; }
constexpr double HzToRadPerSecond(double hz) { return hz * kTwoPi; }
constexpr double RadPerSecondToHz(double omega) { return omega / kTwoPi; }
constexpr double RpmToHz(double rpm) { return rpm / 60.0; }  // revolutions per second
constexpr double HzToRpm(double hz) { return hz * 60.0; }

}  // namespace rubcont
