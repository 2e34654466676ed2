// The levels of model, cheapest first (docs/architecture.md, "The levels"): every result says which
// one produced it (the `level` attribute of each group), and a result file's root attribute `level`
// is the highest of its stages' (HighestLevel in apps/scene.h).
#pragma once

namespace rubcont {

enum class Level {
  kL0,  // the closed form (Mode 1 / Mode 2, Jeffcott)
  kL1,  // rotating waves: co-rotating-frame equilibria
  kL2,  // periodic and relative periodic orbits
  kL3,  // time-marching transients and sweeps
  kL4,  // flexible rotor and stator (Timoshenko finite elements, Craig–Bampton reduction)
};

// "L0" … "L4", as written in result files.
constexpr const char* ToString(Level level) {
  switch (level) {
    case Level::kL0: return "L0";
    case Level::kL1: return "L1";
    case Level::kL2: return "L2";
    case Level::kL3: return "L3";
    case Level::kL4: return "L4";
  }
  return "?";
}

}  // namespace rubcont
