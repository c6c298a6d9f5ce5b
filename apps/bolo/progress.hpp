#pragma once
// A one-line progress bar on stderr, e.g.
//   correct  [#######.....]  112/160 frames  54 fps
// drawn only when stderr is a terminal (never into pipes, logs or tests), at most ~10 times a
// second, and erased when done so the summary on stdout stays clean.

#include <chrono>
#include <cstdint>
#include <string>

namespace bolo::cli {

class Progress {
 public:
  // `enabled` = false never draws; true draws only if stderr is a TTY.
  Progress(std::string label, std::uint64_t total, bool enabled = true);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(std::uint64_t done);
  void finish();  // erases the bar

  // The text of the bar (without carriage return), for a given state; exposed for tests.
  static std::string format(const std::string& label, std::uint64_t done, std::uint64_t total,
                            double fps, int bar_width = 12);

 private:
  void draw(std::uint64_t done);

  std::string label_;
  std::uint64_t total_;
  bool active_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace bolo::cli
