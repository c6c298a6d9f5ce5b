#include "bolo/run/run_status.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

namespace bolo::run {
namespace {

constexpr Clock::duration kBinWidth = std::chrono::microseconds(10);

}  // namespace

void LatencyTally::add(Clock::duration latency) {
  const auto bin = static_cast<std::size_t>(std::max<Clock::rep>(latency / kBinWidth, 0));
  ++bins_[std::min(bin, kBins - 1)];
  ++count_;
  max_ = std::max(max_, latency);
}

Clock::duration LatencyTally::median() const {
  if (count_ == 0) return {};
  std::uint64_t seen = 0;
  for (std::size_t bin = 0; bin < kBins; ++bin) {
    seen += bins_[bin];
    if (2 * seen >= count_) return std::min(max_, kBinWidth * static_cast<Clock::rep>(bin + 1));
  }
  return max_;
}

std::string milliseconds_text(Clock::duration d) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f ms", std::chrono::duration<double, std::milli>(d).count());
  return text;
}

void RunStatus::on_frame(const correct::FrameStats& stats, Clock::duration latency, std::uint64_t skipped_total,
                         Clock::time_point now) {
  ++frames_;
  ++total_frames_;
  breaks_ += stats.carry_over != fw::CarryOver::applied;
  latencies_.push_back(latency);
  report_if_due(skipped_total, now);
}

void RunStatus::on_fault(std::uint64_t skipped_total, Clock::time_point now) { report_if_due(skipped_total, now); }

void RunStatus::report_if_due(std::uint64_t skipped_total, Clock::time_point now) {
  const Clock::duration elapsed = now - second_start_;
  if (elapsed < std::chrono::seconds(1)) return;
  std::string latency = "no frame";
  if (!latencies_.empty()) {
    const auto middle = latencies_.begin() + static_cast<std::ptrdiff_t>(latencies_.size() / 2);
    std::nth_element(latencies_.begin(), middle, latencies_.end());
    latency = "latency median " + milliseconds_text(*middle) + " max " +
              milliseconds_text(*std::max_element(latencies_.begin(), latencies_.end()));
  }
  char fps[32];
  std::snprintf(fps, sizeof fps, "%.1f", static_cast<double>(frames_) / std::chrono::duration<double>(elapsed).count());
  out_ << "run " << std::chrono::duration_cast<std::chrono::seconds>(now - start_).count() << " s: " << fps << " fps, "
       << latency << ", faults " << skipped_total - skipped_at_start_ << ", carry-over breaks " << breaks_ << " ("
       << total_frames_ << " frames)" << std::endl;
  second_start_ = now;
  latencies_.clear();
  frames_ = breaks_ = 0;
  skipped_at_start_ = skipped_total;
}

}  // namespace bolo::run
