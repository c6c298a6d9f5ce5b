#include "bolo/hal/gpio_lines.hpp"

#if defined(BOLO_HAVE_LIBGPIOD)
#include <gpiod.h>
#include <time.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#endif

namespace bolo::hal {

#if defined(BOLO_HAVE_LIBGPIOD)
namespace {

[[noreturn]] void fail(const GpioConfig& c, int line, const char* what) {
  throw std::runtime_error("gpio " + c.chip + (line >= 0 ? " line " + std::to_string(line) : std::string()) +
                           ": " + what + ": " + std::strerror(errno));
}

gpiod_chip* open_chip(const std::string& name) {
  return name.find('/') != std::string::npos ? gpiod_chip_open(name.c_str())
                                             : gpiod_chip_open_by_name(name.c_str());
}

}  // namespace

GpiodLines::GpiodLines(const GpioConfig& config) : config_(config) {
  chip_ = open_chip(config.chip);
  if (!chip_) fail(config, -1, "cannot open the chip");
  try {
    auto line = [&](int offset) {
      gpiod_line* l = gpiod_chip_get_line(chip_, static_cast<unsigned>(offset));
      if (!l) fail(config, offset, "no such line");
      return l;
    };
    if (config.shutter_line >= 0) {
      shutter_ = line(config.shutter_line);
      gpiod_line_request_config rc{"bolo-shutter", GPIOD_LINE_REQUEST_DIRECTION_OUTPUT,
                                   config.shutter_active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0};
      if (gpiod_line_request(shutter_, &rc, 0) != 0) fail(config, config.shutter_line, "cannot request as output");
    }
    if (config.sync_line >= 0) {
      sync_ = line(config.sync_line);
      if (gpiod_line_request_rising_edge_events(sync_, "bolo-sync") != 0)
        fail(config, config.sync_line, "cannot request edge events");
    }
    if (config.ffc_imminent_line >= 0) {
      imminent_ = line(config.ffc_imminent_line);
      gpiod_line_request_config rc{"bolo-ffc-imminent", GPIOD_LINE_REQUEST_DIRECTION_INPUT,
                                   config.ffc_imminent_active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0};
      if (gpiod_line_request(imminent_, &rc, 0) != 0)
        fail(config, config.ffc_imminent_line, "cannot request as input");
    }
  } catch (...) {
    gpiod_chip_close(chip_);  // releases every line requested so far
    throw;
  }
}

GpiodLines::~GpiodLines() { gpiod_chip_close(chip_); }

bool GpiodLines::pulse_shutter() {
  if (!shutter_ || gpiod_line_set_value(shutter_, 1) != 0) return false;
  const timespec pulse{static_cast<time_t>(config_.shutter_pulse_us / 1000000),
                       static_cast<long>(config_.shutter_pulse_us % 1000000) * 1000};
  nanosleep(&pulse, nullptr);
  return gpiod_line_set_value(shutter_, 0) == 0;
}

bool GpiodLines::ffc_imminent() { return imminent_ && gpiod_line_get_value(imminent_) == 1; }

std::size_t GpiodLines::drain_sync_edges(std::span<std::int64_t> out) {
  if (!sync_) return 0;
  std::size_t n = 0;
  const timespec none{0, 0};
  while (n < out.size() && gpiod_line_event_wait(sync_, &none) == 1) {
    gpiod_line_event ev{};
    if (gpiod_line_event_read(sync_, &ev) != 0) break;
    out[n++] = std::int64_t{ev.ts.tv_sec} * 1'000'000'000 + ev.ts.tv_nsec;
  }
  return n;
}

std::vector<GpioChipEntry> list_gpiochips() {
  std::vector<GpioChipEntry> out;
  gpiod_chip_iter* it = gpiod_chip_iter_new();
  if (!it) return out;
  for (gpiod_chip* chip = gpiod_chip_iter_next(it); chip; chip = gpiod_chip_iter_next(it))
    out.push_back({gpiod_chip_name(chip), gpiod_chip_label(chip), gpiod_chip_num_lines(chip)});
  gpiod_chip_iter_free(it);
  return out;
}

bool gpio_backend_available() { return true; }

#else

std::vector<GpioChipEntry> list_gpiochips() { return {}; }
bool gpio_backend_available() { return false; }

#endif

}  // namespace bolo::hal
