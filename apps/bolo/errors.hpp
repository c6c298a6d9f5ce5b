#pragma once
// Errors of the tool. Bad input anywhere is thrown (bolo::cli::Error here, bolo::rec::Error from
// the recording library, ...) with a message naming the file, frame, field or flag; guarded() is
// the one place that turns any of them into `bolo: error: <message>` on stderr and exit code 2.

#include <functional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace bolo::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 2;  // bad input, usage errors: the same code for both

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Builds a message from streamable parts and throws it as bolo::cli::Error.
template <typename... Parts>
[[noreturn]] void fail(const Parts&... parts) {
  std::ostringstream message;
  (message << ... << parts);
  throw Error(message.str());
}

// Prints `bolo: error: <message>` as one line (newlines in the message become "; ").
void print_error(std::ostream& err, const std::string& message);

// Runs `body`; any exception becomes print_error(...) and kExitError.
int guarded(std::ostream& err, const std::function<int()>& body);

}  // namespace bolo::cli
