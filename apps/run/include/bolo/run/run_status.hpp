#pragma once
// What `bolo run` reports while it runs: once a second a line with the frame rate, the
// dequeue-to-sink latency (median and max over that second), the frames skipped for faults and
// the frames corrected without their predecessor (carry-over breaks) in that second.

#include <array>
#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "bolo/correct/frame_observer.hpp"

namespace bolo::run {

using Clock = std::chrono::steady_clock;

// Latencies of a run in 10 µs bins up to 100 ms (beyond: the last bin), and the exact maximum.
class LatencyTally {
 public:
  void add(Clock::duration latency);
  std::uint64_t count() const { return count_; }
  Clock::duration median() const;  // to the bin's upper edge; zero without samples
  Clock::duration max() const { return max_; }

 private:
  static constexpr std::size_t kBins = 10000;
  std::vector<std::uint64_t> bins_ = std::vector<std::uint64_t>(kBins);
  std::uint64_t count_ = 0;
  Clock::duration max_{};
};

class RunStatus {
 public:
  RunStatus(std::ostream& out, Clock::time_point start) : out_(out), start_(start), second_start_(start) {}
  // After each frame reached the sink: its stats, its latency and the frames skipped so far. Prints
  // the second's line when a second has passed since the previous one.
  void on_frame(const correct::FrameStats& stats, Clock::duration latency, std::uint64_t skipped_total,
                Clock::time_point now);
  // After a faulted frame: the same, so that a source that has gone silent still reports.
  void on_fault(std::uint64_t skipped_total, Clock::time_point now);

 private:
  void report_if_due(std::uint64_t skipped_total, Clock::time_point now);

  std::ostream& out_;
  Clock::time_point start_, second_start_;
  std::vector<Clock::duration> latencies_;  // this second's
  std::uint64_t frames_ = 0, breaks_ = 0, skipped_at_start_ = 0, total_frames_ = 0;
};

// Milliseconds with two decimals, as the status lines print them.
std::string milliseconds_text(Clock::duration d);

}  // namespace bolo::run
