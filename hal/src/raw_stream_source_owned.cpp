// The constructor that allocates its buffers, in its own object file: a program that passes its
// own storage (correct_stream) links no operator new.
#include "bolo/hal/raw_stream_source.hpp"

namespace bolo::hal {

RawStreamSource::RawStreamSource(int fd, const RawStreamConfig& config)
    : fd_(fd),
      config_(config),
      owned_bytes_(frame_bytes(config)),
      owned_line_(config.width),
      bytes_(owned_bytes_),
      line_(owned_line_) {}

}  // namespace bolo::hal
