// The commands' one mapping from what they throw to the exit code (apps/commands.h): a scene
// error or an invalid argument is bad input (exit 2, the message on `err`), anything else a
// failure (exit 1).
#pragma once

#include <exception>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/commands.h"
#include "apps/scene.h"

namespace rubcont {

template <class Function>
int Guarded(std::ostream& err, Function&& function) {
  try {
    return function();
  } catch (const SceneError& e) {
    fmt::print(err, "{}\n", e.what());
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    fmt::print(err, "rubcont: {}\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    fmt::print(err, "rubcont: error: {}\n", e.what());
    return kExitFailure;
  }
}

}  // namespace rubcont
