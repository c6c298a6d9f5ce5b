// recording.json: read_recording_json on the input as a file. Properties: what is accepted is
// in range (width, height >= 1; bits 1..32; fps finite and > 0), and write_recording_json writes
// it back to a file that reads back to the same values, unknown keys included.

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "bolo/recording/recording.hpp"
#include "fuzz_support.hpp"

using namespace bolo;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path file = fuzz::scratch_dir() / "recording.json";
  fuzz::write_file(file, std::span(data, size));
  rec::RecordingInfo info;
  try {
    info = rec::read_recording_json(file);
  } catch (const rec::Error&) {
    return 0;
  }
  BOLO_FUZZ_CHECK(info.width >= 1 && info.height >= 1);
  BOLO_FUZZ_CHECK(info.bits >= 1 && info.bits <= 32);
  BOLO_FUZZ_CHECK(!info.fps || (std::isfinite(*info.fps) && *info.fps > 0));
  BOLO_FUZZ_CHECK(info.extra.is_object());
  const std::filesystem::path copy = fuzz::scratch_dir() / "recording-copy.json";
  try {
    rec::write_recording_json(copy, info);
    const rec::RecordingInfo again = rec::read_recording_json(copy);
    BOLO_FUZZ_CHECK(again.width == info.width && again.height == info.height);
    BOLO_FUZZ_CHECK(again.bits == info.bits && again.fps == info.fps);
    BOLO_FUZZ_CHECK(again.units == info.units);
    BOLO_FUZZ_CHECK(again.sensor == info.sensor && again.source == info.source &&
                    again.notes == info.notes);
    BOLO_FUZZ_CHECK(again.extra == info.extra);
  } catch (const rec::Error& e) {
    std::fprintf(stderr, "accepted recording.json did not round-trip: %s\n", e.what());
    BOLO_FUZZ_CHECK(!"an accepted recording.json was refused when written and read back");
  }
  return 0;
}
