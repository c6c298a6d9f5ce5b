// The real-device GPIO check's rules on hand-made marks: a clean stream passes, and each way a
// camera's lines can go wrong is named.

#include <catch2/catch.hpp>

#include "gpio_camera_check.hpp"

using bolo::hil::GpioCameraFrame;
using bolo::hil::GpioCameraPlan;
using bolo::hil::check_gpio_camera;

namespace {

constexpr std::int64_t kPeriod = 33'000'000, kLatency = 2'000'000;

// Frames every 33 ms, each with a pulse 2 ms before it; frame `shutter` follows our pulse.
std::vector<GpioCameraFrame> clean_stream(std::size_t n, std::optional<std::size_t> shutter = {}) {
  std::vector<GpioCameraFrame> f(n);
  for (std::size_t i = 0; i < n; ++i) {
    f[i].timestamp_ns = 1'000'000'000 + static_cast<std::int64_t>(i) * kPeriod;
    f[i].timestamp_valid = true;
    f[i].marks.sync_matched = true;
    f[i].marks.sync_ns = f[i].timestamp_ns - kLatency;
    f[i].marks.latency_ns = kLatency;
    f[i].marks.after_shutter = shutter && *shutter == i;
  }
  return f;
}

bool mentions(const bolo::hil::GpioCameraResult& r, const std::string& text) {
  for (const std::string& f : r.failures)
    if (f.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("gpio camera check: a clean stream with a sync pulse per frame and one shutter passes", "[hal][gpio]") {
  const auto frames = clean_stream(20, 10);
  const auto r = check_gpio_camera(frames, {true, 10});
  CHECK(r.failures.empty());
  CHECK(r.median_interval_ns == kPeriod);
  CHECK(r.median_latency_ns == kLatency);
  CHECK(r.shutter_marked == 1);
}

TEST_CASE("gpio camera check: a missing pulse, a frame without one, a late match are named", "[hal][gpio]") {
  auto missing = clean_stream(20);
  missing[7].marks.sync_ns = missing[6].marks.sync_ns;  // no pulse of its own: matched the previous
  missing[7].marks.latency_ns = missing[7].timestamp_ns - missing[7].marks.sync_ns;
  CHECK(mentions(check_gpio_camera(missing, {true, {}}), "previous frame's sync edge"));

  auto unmatched = clean_stream(20);
  unmatched[5].marks.sync_matched = false;
  CHECK(mentions(check_gpio_camera(unmatched, {true, {}}), "no sync edge"));

  auto late = clean_stream(20);
  late[9].marks.latency_ns = 2 * kPeriod;
  CHECK(mentions(check_gpio_camera(late, {true, {}}), "1.5 frame periods"));

  auto untimed = clean_stream(20);
  untimed[3].timestamp_valid = false;
  CHECK(mentions(check_gpio_camera(untimed, {true, {}}), "without a time stamp"));

  // The first frame may precede the line's first edge.
  auto first = clean_stream(20);
  first[0].marks.sync_matched = false;
  CHECK(check_gpio_camera(first, {true, {}}).failures.empty());
  // Without a sync line the marks are not judged.
  CHECK(check_gpio_camera(unmatched, {false, {}}).failures.empty());
}

TEST_CASE("gpio camera check: the shutter marks exactly the frame after the pulse", "[hal][gpio]") {
  CHECK(mentions(check_gpio_camera(clean_stream(20, 11), {true, 10}), "is not marked"));
  auto twice = clean_stream(20, 10);
  twice[12].marks.after_shutter = true;
  CHECK(mentions(check_gpio_camera(twice, {true, 10}), "2 frames marked"));
  CHECK(mentions(check_gpio_camera(clean_stream(20, 4), {true, {}}), "nobody sent"));
  CHECK(mentions(check_gpio_camera(clean_stream(8), {true, 10}), "ended before"));
}
