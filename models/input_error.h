// A model input that cannot be built, named. std::invalid_argument with a tag saying which input
// broke its rule ("modes", "rotor section", …), so that a caller that knows the input by another
// name (the scene loader's keys) can point at it without reading the message.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace rubcont {

class ModelInputError : public std::invalid_argument {
 public:
  ModelInputError(std::string input, const std::string& message)
      : std::invalid_argument(message), input_(std::move(input)) {}
  const std::string& input() const { return input_; }

 private:
  std::string input_;
};

}  // namespace rubcont
