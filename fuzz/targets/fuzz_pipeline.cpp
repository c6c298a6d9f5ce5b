// The firmware pipeline (NUC -> bad pixels -> two-frame corrector) driven directly by the input:
// after the configuration (size up to 40x40, time constants, NUC tables, mask, stuck rails, a
// short arena now and then), each operation is one of
//   begin_frame with a header of arbitrary size, sequence, timestamp, exposure, readout, FFC
//   state and temperatures (or the "next" of each, so the corrector gets to apply carry-over),
//   push_line with an arbitrary row and length (or the next row at the frame's width), pixels
//   from the input or generated with rail values,
//   end_frame, a whole well-formed frame (line by line or as one push_lines run), or new time
//   constants.
// Properties: no access outside any buffer (every line and table is an exactly sized heap
// block), no undefined behaviour, as many lines out as in per frame, no line wider than the
// widest pushed.

#include <cstdint>
#include <memory>

#include "fuzz_support.hpp"
#include "pipeline_harness.hpp"

using namespace bolo;

namespace {

constexpr std::uint32_t kMaxSide = 40;       // configured frame size
constexpr std::uint32_t kMaxHeaderSide = 48;  // header sizes beyond the configured one
constexpr std::uint32_t kMaxLine = 80;        // pushed line lengths
constexpr int kMaxOps = 2048;

struct Driver {
  fuzz::ByteReader& in;
  fuzz::FuzzPipeline& pipe;
  fuzz::CheckingSink& sink;
  fuzz::Prng prng;
  std::uint32_t width, height;  // configured
  fw::FrameHeader last{};
  std::uint32_t next_row = 0;

  fw::FrameHeader header(std::uint8_t mode) {
    fw::FrameHeader h;
    h.width = (mode & 1) != 0 ? width : in.range(0, kMaxHeaderSide);
    h.height = (mode & 2) != 0 ? height : in.range(0, kMaxHeaderSide);
    h.sequence = (mode & 4) != 0 ? last.sequence + 1 : in.u64();
    h.sequence_valid = (mode & 8) != 0 || in.flag();
    // Unsigned arithmetic: the harness itself must not overflow.
    h.timestamp_ns = (mode & 16) != 0
                         ? static_cast<std::int64_t>(static_cast<std::uint64_t>(last.timestamp_ns) + in.u32())
                         : static_cast<std::int64_t>(in.u64());
    h.timestamp_valid = (mode & 32) != 0 || in.flag();
    h.exposure_ns = in.u32();
    h.readout_ns = in.u32();
    h.ffc = static_cast<fw::FfcState>(in.u8() % 6);  // 5: not an enumerator
    if ((mode & 64) != 0) {
      h.fpa_temp_mc = static_cast<std::int32_t>(in.u32());
      h.housing_temp_mc = static_cast<std::int32_t>(in.u32());
    }
    return h;
  }

  void begin(const fw::FrameHeader& h) {
    last = h;
    next_row = 0;
    pipe.input().begin_frame(h);
    sink.lines_in = 0;
  }
  void end() {
    pipe.input().end_frame();
    sink.lines_in = 0;
  }
  void push(std::uint32_t row, std::uint32_t length, bool from_input, std::uint8_t rails) {
    std::unique_ptr<fw::Pixel[]> line(new fw::Pixel[length == 0 ? 1 : length]);
    for (std::uint32_t x = 0; x < length; ++x) {
      line[x] = from_input ? in.u16() : static_cast<fw::Pixel>(prng.next());
      if (rails != 0 && (prng.next() & 7) == 0) {
        constexpr fw::Pixel kRails[] = {0, 0x3FFF, 0xFFFF, 1};
        line[x] = kRails[rails & 3];
      }
    }
    ++sink.lines_in;
    pipe.input().push_line(row, fw::LineView(line.get(), length));
  }

  // Rows 0..count-1 as one run, in one exactly sized block (no padding between rows).
  void push_run(std::uint32_t length, std::uint32_t count, std::uint8_t rails) {
    const std::size_t n = std::size_t{length} * count;
    std::unique_ptr<fw::Pixel[]> block(new fw::Pixel[n == 0 ? 1 : n]);
    for (std::size_t i = 0; i < n; ++i) {
      block[i] = static_cast<fw::Pixel>(prng.next());
      if ((prng.next() & 7) == 0) {
        constexpr fw::Pixel kRails[] = {0, 0x3FFF, 0xFFFF, 1};
        block[i] = kRails[rails & 3];
      }
    }
    sink.lines_in += count;
    pipe.input().push_lines(0, count, block.get(), length, length);
  }

  void step() {
    const std::uint8_t op = in.u8();
    switch (op % 8) {
      case 0:
      case 1:
        begin(header(in.u8()));
        break;
      case 2:
      case 3:
      case 4: {
        const std::uint8_t mode = in.u8();
        const std::uint32_t row = (mode & 1) != 0   ? next_row++
                                  : (mode & 2) != 0 ? in.range(0, kMaxHeaderSide)
                                                    : in.u32();
        const std::uint32_t length = (mode & 4) != 0 ? last.width : in.range(0, kMaxLine);
        push(row, length, (mode & 8) != 0, static_cast<std::uint8_t>(mode >> 4));
        break;
      }
      case 5:
        end();
        break;
      case 6: {  // a whole frame, in order, at the configured size
        fw::FrameHeader h = header(0x3F);
        begin(h);
        const std::uint8_t rails = in.u8();
        if ((rails & 0x80) != 0) {
          push_run(width, height, rails);  // the same rows as one push_lines
        } else {
          for (std::uint32_t row = 0; row < height; ++row) push(row, width, false, rails);
        }
        end();
        break;
      }
      case 7:
        pipe.pipeline->corrector().set_time_constants({in.u32(), in.u32()});
        break;
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  const std::uint32_t width = in.range(0, kMaxSide);
  const std::uint32_t height = in.range(0, kMaxSide);
  fuzz::CheckingSink sink(kMaxLine);
  fuzz::FuzzPipeline pipe(in, width, height, sink);
  Driver driver{in, pipe, sink, fuzz::Prng(in.u32()), width, height};
  for (int ops = 0; ops < kMaxOps && !in.empty(); ++ops) driver.step();
  return 0;
}
