// Seek frame assembly and parsing (bolo::hal::SeekFrameParser), the frame through
// SeekImageCorrector. Input: byte 0 picks the model
// (bit 0: Compact / CompactPro); then a list of chunk lengths (u16 each, a 0 ends the list; at
// most 32); the rest is the byte stream the chunks are cut from (repeated to fill them).
// Properties: no crash; `complete` exactly when the chunks add up to the frame size, `overflow`
// when they pass it, `aborted` on an empty chunk; a parsed frame's type/counter are its words;
// the dead-pixel map holds exactly dead_pixels() ones, all fillable unless all are dead, and a
// frame minus itself as shutter is 0x4000 everywhere.

#include <vector>

#include "bolo/hal/seek_frame_parser.hpp"
#include "bolo/hal/seek_image.hpp"
#include "fuzz_support.hpp"

using namespace bolo;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  const hal::SeekModel& model = (in.u8() & 1) ? hal::kSeekCompactPro : hal::kSeekCompact;
  std::vector<std::uint32_t> lengths;
  for (int i = 0; i < 32; ++i) {
    const std::uint32_t len = in.u16();
    if (len == 0 && !lengths.empty()) break;
    lengths.push_back(len);
  }
  const std::span<const std::uint8_t> stream = in.rest();

  static std::vector<std::uint8_t> chunk;  // reused across runs: the fuzzer's memory stays flat
  hal::SeekFrameParser parser(model);
  parser.begin();
  std::size_t sent = 0, from = 0;
  hal::SeekChunk last = hal::SeekChunk::need_more;
  for (std::uint32_t len : lengths) {
    chunk.resize(len);
    for (std::uint32_t i = 0; i < len; ++i)
      chunk[i] = stream.empty() ? static_cast<std::uint8_t>(i * 31) : stream[(from + i) % stream.size()];
    from += len;
    last = parser.add_chunk(chunk);
    if (len == 0) {
      BOLO_FUZZ_CHECK(last == hal::SeekChunk::aborted);
      break;
    }
    if (sent + len > model.frame_bytes()) {
      BOLO_FUZZ_CHECK(last == hal::SeekChunk::overflow);
      BOLO_FUZZ_CHECK(parser.received() == 0);
      break;
    }
    sent += len;
    BOLO_FUZZ_CHECK(parser.received() == sent);
    BOLO_FUZZ_CHECK((last == hal::SeekChunk::complete) == (sent == model.frame_bytes()));
    if (last == hal::SeekChunk::complete) break;
  }

  // Parse the stream as a whole frame when it is one (padded or cut to size otherwise).
  static std::vector<std::uint8_t> frame;
  frame.assign(model.frame_bytes(), 0);
  for (std::size_t i = 0; i < frame.size() && !stream.empty(); ++i) frame[i] = stream[i % stream.size()];
  hal::SeekFrameInfo info;
  BOLO_FUZZ_CHECK(parser.parse(frame, info));
  const auto word = [&](std::uint32_t w) { return static_cast<std::uint16_t>(frame[2 * w] | (frame[2 * w + 1] << 8)); };
  BOLO_FUZZ_CHECK(info.type == word(model.type_word));
  BOLO_FUZZ_CHECK(info.counter == word(model.counter_word));
  BOLO_FUZZ_CHECK(info.kind == hal::seek_frame_kind(info.type));
  // The same frame as start-up, shutter and image frame: the map counts its ones, every dead
  // pixel can be filled unless all are dead, and each live pixel comes out as exactly 0x4000.
  static hal::SeekImageCorrector corrector(hal::kSeekCompactPro);
  static hal::SeekImageCorrector compact_corrector(hal::kSeekCompact);
  hal::SeekImageCorrector& c = model.family == hal::SeekFamily::compact_pro ? corrector : compact_corrector;
  c.take_startup(parser.words());
  std::uint32_t ones = 0;
  for (std::uint8_t d : c.dead_map()) ones += d;
  BOLO_FUZZ_CHECK(ones == c.dead_pixels());
  BOLO_FUZZ_CHECK(c.unfillable_pixels() == (ones == model.crop.pixels() ? ones : 0u));
  c.take_shutter(parser.words());
  c.correct(parser.words(), true);
  for (std::size_t i = 0; i < c.image().size(); ++i)
    if (!c.dead_map()[i]) BOLO_FUZZ_CHECK(c.image()[i] == hal::kSeekShutterOffset);
  BOLO_FUZZ_CHECK(!parser.parse(std::span<const std::uint8_t>(frame).first(frame.size() - 1), info));
  if (last == hal::SeekChunk::complete) BOLO_FUZZ_CHECK(parser.parse_received(info));
  return 0;
}
