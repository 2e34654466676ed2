// Scales that look like unit mistakes (a scene written in mm, a radius of 1000 km): the rules
// from the physics of a rubbing rotor, each giving the likely mistake or nothing. They warn, they
// do not refuse: an unusual machine may break one on purpose. The commands print them naming the
// scene key (apps/plan_check.h); a scene that breaks none is unchanged by them.
#pragma once

#include <string>

#include "models/rub_model.h"

namespace rubcont {

// Lengths of a rotor and its stator (radii, clearances, spans, diameters) lie within
// [kSmallestRotorLength, kLargestRotorLength]: the largest turbine-generator rotors are about
// 1 m across and 15 m long between bearings, their spans between contact planes shorter; a
// clearance below 1 µm is below the roughness of a machined surface.
inline constexpr double kLargestRotorLength = 20.0;   // [m]
inline constexpr double kSmallestRotorLength = 1e-6;  // [m]
// The radius-to-clearance ratio R/C of a contact lies within [kSmallestRci, kLargestRci]: seals
// and rub-prone clearances are 1e-4 … 1e-2 of the radius (the committed scenes' R/C 100 … 125), a
// journal bearing's 1e-3; a clearance of a fifth of the radius is no clearance of a rotor, and
// R/C = 1e5 is a 38 mm rotor with a 0.4 µm clearance.
inline constexpr double kSmallestRci = 5.0;
inline constexpr double kLargestRci = 1e5;
// The surface speed R·ω stays below kFastestSurfaceSpeed [m/s]: the burst speed of steel and
// titanium rotors is 500–700 m/s at their rim (gas-turbine blade tips run at about 500 m/s).
inline constexpr double kFastestSurfaceSpeed = 1000.0;
// The speed range reaches within kKneeSpeedFactor of the knee (RollingKneeSpeed): below
// knee/factor no contact can roll against a resonance, above knee·factor the rolling whirl
// precesses at ten times the structure's lowest natural frequency. Every committed scene's range
// holds its knee (its low ends at 0.38 … 1.0 times it, its high ends at 1.06 … 6.8); a mass in g
// or a stiffness in N/mm moves the knee
// 31.6-fold, which this factor catches for a range of up to 3 times the knee on that side.
inline constexpr double kKneeSpeedFactor = 10.0;

// "<value> m is larger than any rotor (20 m): a length in mm written as m?" or the like; empty
// when `metres` lies within the limits above (or is 0).
std::string LengthScaleMistake(double metres);

// R/C outside [kSmallestRci, kLargestRci]: the likely mistake; empty otherwise.
std::string ClearanceRatioMistake(double radius, double clearance);

// R·ω above kFastestSurfaceSpeed at `omega` [rad/s]: the likely mistake; empty otherwise.
std::string SurfaceSpeedMistake(double radius, double omega);

// The lowest natural frequency [rad/s] of `structure` with each contact's rotor coordinate pinned
// to its stator coordinate (rolling without clearance), undamped and without spin: the first of
// StructureModes (models/flexible.h); NaN when it has none. Two-point rotor with symmetric bodies:
// √((k_L + k_R)/(m_r + m_s)), its translation. Throws std::invalid_argument for an invalid
// structure (RubStructure::Validate).
double PinnedNaturalFrequency(const RubStructure& structure);

// The speed [rad/s] at which a rolling contact's backward precession (R/C)·ω reaches the pinned
// natural frequency, the lowest over the contacts: min_k (C_k/R_k)·ω_n. Near it the rolling whirl
// meets its resonance and the whirl ↔ whip jumps begin (case A(a): 52 rpm against its knee at
// 50.96 rpm). NaN when PinnedNaturalFrequency is.
double RollingKneeSpeed(const RubStructure& structure);

// A speed range [low, high] (rad/s) that lies wholly more than kKneeSpeedFactor away from the
// knee: the likely mistake (a mass, a stiffness or a length in the wrong unit); empty otherwise.
std::string SpeedRangeMistake(double knee, double low, double high);

}  // namespace rubcont
