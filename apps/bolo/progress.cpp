#include "bolo/progress.hpp"

#include <cstdio>
#include <sstream>

#include <unistd.h>

namespace bolo::cli {

Progress::Progress(std::string label, std::uint64_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      active_(enabled && ::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() { finish(); }

std::string Progress::format(const std::string& label, std::uint64_t done, std::uint64_t total,
                             double fps, int bar_width) {
  const double fraction =
      total == 0 ? 1.0 : static_cast<double>(done > total ? total : done) / static_cast<double>(total);
  const int filled = static_cast<int>(fraction * bar_width + 0.5);
  std::ostringstream line;
  line << label << "  [" << std::string(static_cast<std::size_t>(filled), '#')
       << std::string(static_cast<std::size_t>(bar_width - filled), '.') << "]  " << done << '/'
       << total << " frames";
  if (fps > 0) line << "  " << static_cast<long long>(fps + 0.5) << " fps";
  return line.str();
}

void Progress::draw(std::uint64_t done) {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fps = seconds > 0 ? static_cast<double>(done) / seconds : 0.0;
  const std::string line = format(label_, done, total_, fps);
  std::fprintf(stderr, "\r%s\033[K", line.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::update(std::uint64_t done) {
  if (!active_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && done < total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(done);
}

void Progress::finish() {
  if (active_ && drawn_) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  }
  drawn_ = false;
  active_ = false;
}

}  // namespace bolo::cli
