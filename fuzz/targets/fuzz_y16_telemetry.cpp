// UVC Y16 frames with Lepton telemetry rows (bolo::hal::Y16Frame, decode_lepton_telemetry).
// Input: width (u16, 0..400), image rows (u16, 0..300), telemetry rows (u8, 0..3), bytes per
// line (u16), then the buffer. Properties: no crash, nothing read outside the buffer (ASan);
// check() is ok exactly when the layout is sane and the buffer holds min_bytes(); every image
// row reads back the buffer's little-endian words; telemetry decodes exactly when the layout has
// telemetry rows at least 80 words wide, and its fields are the words of the first one.

#include <vector>

#include "bolo/hal/y16_frame.hpp"
#include "fuzz_support.hpp"

using namespace bolo;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  hal::Y16Layout layout;
  layout.width = in.u16() % 401;
  layout.image_rows = in.u16() % 301;
  layout.telemetry_rows = in.u8() % 4;
  layout.bytes_per_line = in.u16();
  const std::span<const std::uint8_t> bytes = in.rest();

  const hal::Y16Check c = hal::Y16Frame::check(bytes, layout);
  const bool sane = layout.width > 0 && layout.image_rows > 0 && layout.stride() >= layout.width * 2u;
  BOLO_FUZZ_CHECK((c == hal::Y16Check::bad_layout) == !sane);
  if (sane) BOLO_FUZZ_CHECK((c == hal::Y16Check::ok) == (bytes.size() >= layout.min_bytes()));
  if (c != hal::Y16Check::ok) return 0;

  const hal::Y16Frame frame(bytes, layout);
  static std::vector<std::uint16_t> row;
  row.assign(layout.width, 0);
  for (std::uint32_t r = 0; r < layout.image_rows; ++r) {
    frame.image_row(r, row);
    const std::size_t at = std::size_t{r} * layout.stride();
    BOLO_FUZZ_CHECK(row[0] == (bytes[at] | (bytes[at + 1] << 8)));
    const std::size_t last = at + 2 * (layout.width - 1);
    BOLO_FUZZ_CHECK(row[layout.width - 1] == (bytes[last] | (bytes[last + 1] << 8)));
  }
  hal::LeptonTelemetry t;
  const bool decoded = frame.telemetry(t);
  BOLO_FUZZ_CHECK(decoded == (layout.telemetry_rows > 0 && layout.width >= hal::kLeptonTelemetryWords));
  if (decoded) {
    const std::size_t a = std::size_t{layout.image_rows} * layout.stride();
    const auto word = [&](std::size_t w) { return static_cast<std::uint16_t>(bytes[a + 2 * w] | (bytes[a + 2 * w + 1] << 8)); };
    BOLO_FUZZ_CHECK(t.fpa_temp_ck == word(24));
    BOLO_FUZZ_CHECK(t.housing_temp_ck == word(26));
    BOLO_FUZZ_CHECK(t.frame_counter == (word(20) | (std::uint32_t{word(21)} << 16)));
    BOLO_FUZZ_CHECK(static_cast<unsigned>(t.ffc_state) == ((word(3) >> 4) & 3u));
    BOLO_FUZZ_CHECK(t.time_at_last_ffc_ms == (word(30) | (std::uint32_t{word(31)} << 16)));
  }
  return 0;
}
