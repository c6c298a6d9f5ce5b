#pragma once
// Builds a message from streamable parts and throws it as bolo::correct::Error.

#include <sstream>

#include "bolo/correct/correct_recording.hpp"

namespace bolo::correct {

template <typename... Parts>
[[noreturn]] void fail(const Parts&... parts) {
  std::ostringstream message;
  (message << ... << parts);
  throw Error(message.str());
}

}  // namespace bolo::correct
