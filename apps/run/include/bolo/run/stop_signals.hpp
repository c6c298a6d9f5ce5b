#pragma once
// SIGINT and SIGTERM as a request to stop, while a StopSignals lives: the run finishes the frame
// in hand, commits its sink and exits 0. A second such signal acts as it would without this (the
// handlers are one-shot). SIGPIPE is ignored meanwhile, so a reader that closes the pipe of raw:-
// is a write error naming the sink instead of a silent death. One at a time per process.

#include <string>

namespace bolo::run {

class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The signal that asked to stop (SIGINT, SIGTERM), 0 if none came.
  static int received();
};

// "SIGINT", "SIGTERM", else "signal N".
std::string signal_name(int signal);

}  // namespace bolo::run
