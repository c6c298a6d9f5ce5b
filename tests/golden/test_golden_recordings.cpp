// Golden hashes of every output frame of the firmware pipeline over the shared real recordings.
// Reports SKIP where ../shared/data is absent. BOLO_GOLDEN_PRINT=1 prints the hashes.

#include <catch2/catch.hpp>

#include <cstdlib>

#include "../firmware/frame_collector.hpp"
#include "../test_support.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "bolo/hal/recording_player.hpp"
#include "golden_cases.hpp"

using namespace bolo;

namespace {

std::uint64_t frame_hash(const std::vector<fw::Pixel>& frame) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (fw::Pixel v : frame)
    for (int byte = 0; byte < 2; ++byte) {
      h ^= static_cast<std::uint8_t>(v >> (8 * byte));
      h *= 0x100000001b3ull;
    }
  return h;
}

// A sink that hashes each whole frame as it completes.
class FrameHasher final : public fw::LineSink {
 public:
  FrameHasher(std::uint32_t w, std::uint32_t h) : collector_(w, h) {}
  void begin_frame(const fw::FrameHeader& hd) override { collector_.begin_frame(hd); }
  void push_line(std::uint32_t row, fw::LineView line) override { collector_.push_line(row, line); }
  void end_frame() override {
    collector_.end_frame();
    hashes.push_back(frame_hash(collector_.frame()));
  }
  std::vector<std::uint64_t> hashes;

 private:
  bolo::test::HashingCollector collector_;
};

}  // namespace

TEST_CASE("golden frame hashes over the shared real recordings", "[golden][shared]") {
  const auto golden =
      bolo::test::read_golden(std::string(BOLO_TESTS_DIR) + "/golden/recordings.golden");
  const bool print = std::getenv("BOLO_GOLDEN_PRINT") != nullptr;
  for (const char* name : {"lepton3-possum", "lepton35-trailcam-ffc", "flirone-lepton-telemetry",
                           "flir-t1030-hand"}) {
    const auto dir = bolo::test::shared_recording(name);
    if (dir.empty()) return;  // skipped: no shared data
    hal::RecordingPlayer player(dir);
    const auto format = player.format();
    fw::PipelineConfig cfg;
    cfg.corrector.width = format.width;
    cfg.corrector.height = format.height;
    cfg.corrector.tau = {12'000'000, 12'000'000};
    cfg.corrector.default_exposure_ns = 8'000'000;
    cfg.corrector.default_readout_ns = 20'000'000;
    cfg.use_bad_pixels = true;
    cfg.bad_pixels.stuck_high = static_cast<fw::Pixel>((1u << format.bits) - 1);
    std::vector<fw::Pixel> arena(fw::Pipeline::arena_pixels(cfg));
    FrameHasher sink(format.width, format.height);
    fw::Pipeline pipeline(cfg, arena, sink);
    while (player.stream_frame(pipeline.input()) == hal::StreamStatus::frame) {
    }
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < sink.hashes.size(); ++i) {
      const std::string key = std::string(name) + ":" + std::to_string(i);
      const std::string hash = bolo::test::hex64(sink.hashes[i]);
      if (print) std::printf("%s %s\n", key.c_str(), hash.c_str());
      const auto it = golden.find(key);
      if (it == golden.end() || it->second != hash) {
        if (mismatches < 5) UNSCOPED_INFO("frame " << key << ": got " << hash);
        ++mismatches;
      }
    }
    INFO("recording " << name << ": " << sink.hashes.size() << " frames");
    CHECK(sink.hashes.size() == player.recording().frame_count());
    CHECK(mismatches == 0);
  }
}
