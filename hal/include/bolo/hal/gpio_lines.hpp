#pragma once
// The camera's GPIO lines as the pipeline uses them: a shutter/FFC trigger output, a frame-sync
// input with timestamped edges, an "FFC imminent" input. GpioLines is the seam (tests drive it
// directly); GpiodLines is the libgpiod 1.6 implementation (built where libgpiod is found,
// BOLO_HAVE_LIBGPIOD). Edge times are CLOCK_MONOTONIC nanoseconds, the clock V4L2 stamps
// frames with, so sync-to-frame latency is a subtraction.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

struct gpiod_chip;  // libgpiod's, in the global namespace
struct gpiod_line;

namespace bolo::hal {

class GpioLines {
 public:
  virtual ~GpioLines() = default;
  // Drives the trigger line active for the configured pulse; false when there is none or it failed.
  virtual bool pulse_shutter() = 0;
  // The FFC-imminent input's level (false when not configured).
  virtual bool ffc_imminent() = 0;
  // Sync edges that arrived since the last call, oldest first, up to out.size(); never blocks.
  virtual std::size_t drain_sync_edges(std::span<std::int64_t> out) = 0;
};

struct GpioConfig {
  std::string chip;                    // "gpiochip0" (or a path /dev/gpiochip0)
  int shutter_line = -1;               // output; -1 = none
  bool shutter_active_low = false;
  std::uint32_t shutter_pulse_us = 10000;
  int sync_line = -1;                  // input, rising edges; -1 = none
  int ffc_imminent_line = -1;          // input; -1 = none
  bool ffc_imminent_active_low = false;
};

#if defined(BOLO_HAVE_LIBGPIOD)
class GpiodLines final : public GpioLines {
 public:
  // Throws std::runtime_error naming the chip and line that could not be opened or requested.
  explicit GpiodLines(const GpioConfig& config);
  ~GpiodLines() override;
  GpiodLines(const GpiodLines&) = delete;
  GpiodLines& operator=(const GpiodLines&) = delete;
  bool pulse_shutter() override;
  bool ffc_imminent() override;
  std::size_t drain_sync_edges(std::span<std::int64_t> out) override;

 private:
  GpioConfig config_;
  ::gpiod_chip* chip_ = nullptr;
  ::gpiod_line* shutter_ = nullptr;
  ::gpiod_line* sync_ = nullptr;
  ::gpiod_line* imminent_ = nullptr;
};
#endif

struct GpioChipEntry {
  std::string name, label;
  unsigned lines = 0;
};
// The gpiochips present (empty without libgpiod).
std::vector<GpioChipEntry> list_gpiochips();
bool gpio_backend_available();

}  // namespace bolo::hal
