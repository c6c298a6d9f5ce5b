// Raw Y16 stream source (bolo::hal::RawStreamSource) read through a pipe into the firmware
// Pipeline. The first bytes configure the source and the pipeline (size up to 64x64, timing,
// NUC, bad pixels); the rest is the byte stream. Properties: no crash; frames delivered x frame
// bytes + a short tail == stream size; one short transfer iff there is a tail; every delivered
// frame reaches the output with all its lines, and the corrector counted each of them.

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "bolo/hal/raw_stream_source.hpp"
#include "fuzz_support.hpp"
#include "pipeline_harness.hpp"

using namespace bolo;

namespace {

// A read end holding exactly `bytes`, at end of file after them: a pipe when it can hold them
// (the source then reads it as from a capture tool), an in-memory file otherwise.
int stream_fd(std::span<const std::uint8_t> bytes) {
  int fds[2];
  if (::pipe(fds) == 0) {
    const long want = static_cast<long>(bytes.size() < 4096 ? 4096 : bytes.size());
    if (::fcntl(fds[1], F_SETPIPE_SZ, want) >= want || bytes.size() <= 4096) {
      std::size_t done = 0;
      while (done < bytes.size()) {
        const ssize_t n = ::write(fds[1], bytes.data() + done, bytes.size() - done);
        if (n <= 0 && errno != EINTR) break;
        if (n > 0) done += static_cast<std::size_t>(n);
      }
      ::close(fds[1]);
      if (done == bytes.size()) return fds[0];
      ::close(fds[0]);
    } else {
      ::close(fds[0]);
      ::close(fds[1]);
    }
  }
  const int fd = ::memfd_create("bolo-fuzz-raw", 0);
  BOLO_FUZZ_CHECK(fd >= 0);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    BOLO_FUZZ_CHECK(n > 0 || errno == EINTR);
    if (n > 0) done += static_cast<std::size_t>(n);
  }
  BOLO_FUZZ_CHECK(::lseek(fd, 0, SEEK_SET) == 0);
  return fd;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  hal::RawStreamConfig raw;
  raw.width = in.range(0, 64);
  raw.height = in.range(0, 64);
  raw.bits = in.range(1, 16);
  raw.frame_period_ns = in.u32();
  raw.exposure_ns = in.u32();
  raw.readout_ns = in.u32();
  fuzz::CheckingSink sink(raw.width);
  fuzz::FuzzPipeline pipeline(in, raw.width, raw.height, sink);
  const std::span<const std::uint8_t> stream = in.rest();

  const int fd = stream_fd(stream);
  hal::RawStreamSource source(fd, raw);
  const std::uint64_t frame_bytes = std::uint64_t{raw.width} * raw.height * 2;
  const std::uint64_t max_calls = (frame_bytes == 0 ? 0 : stream.size() / frame_bytes) + 2;
  std::uint64_t frames = 0, calls = 0;
  for (;; ++calls) {
    BOLO_FUZZ_CHECK(calls <= max_calls);
    const std::uint64_t lines_before = sink.total_lines;
    sink.lines_in = raw.height;  // what the source pushes for a whole frame
    const hal::StreamStatus status = source.stream_frame(pipeline.input());
    if (status == hal::StreamStatus::frame) {
      ++frames;
      BOLO_FUZZ_CHECK(sink.total_lines - lines_before == raw.height);
      continue;
    }
    BOLO_FUZZ_CHECK(sink.total_lines == lines_before);
    if (status == hal::StreamStatus::end_of_stream) break;
  }
  ::close(fd);

  const hal::SourceStats stats = source.stats();
  BOLO_FUZZ_CHECK(stats.frames_delivered == frames);
  BOLO_FUZZ_CHECK(sink.frames_begun == frames && sink.frames_ended == frames);
  BOLO_FUZZ_CHECK(pipeline.pipeline->corrector().totals().frames == frames);
  if (frame_bytes == 0) {
    BOLO_FUZZ_CHECK(frames == 0);
  } else {
    const std::uint64_t tail = stream.size() - frames * frame_bytes;
    BOLO_FUZZ_CHECK(frames * frame_bytes <= stream.size() && tail < frame_bytes);
    BOLO_FUZZ_CHECK(stats.short_transfers == (tail > 0 ? 1u : 0u));
    BOLO_FUZZ_CHECK(stats.corrupt_transfers == 0);
  }
  return 0;
}
