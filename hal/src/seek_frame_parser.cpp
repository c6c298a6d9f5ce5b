#include "bolo/hal/seek_frame_parser.hpp"

#include <cstring>

namespace bolo::hal {

SeekFrameKind seek_frame_kind(std::uint16_t type) {
  switch (type) {
    case 3: return SeekFrameKind::image;
    case 1: return SeekFrameKind::shutter;
    case 4: return SeekFrameKind::startup;
    case 6: return SeekFrameKind::before_calibration;
    case 20: return SeekFrameKind::after_calibration;
    case 7:
    case 8: return SeekFrameKind::startup_calibration;
    default: return SeekFrameKind::other;
  }
}

bool seek_frame_type_known(std::uint16_t type) {
  switch (type) {
    case 9:
    case 14:
    case 25:
    case 26:
    case 27:
    case 28: return true;
    default: return seek_frame_kind(type) != SeekFrameKind::other;
  }
}

SeekFrameParser::SeekFrameParser(const SeekModel& model)
    : model_(model),
      bytes_(model.frame_bytes()),
      words_(model.pixels()) {}

SeekChunk SeekFrameParser::add_chunk(std::span<const std::uint8_t> chunk) {
  if (chunk.empty()) return SeekChunk::aborted;
  if (chunk.size() > bytes_.size() - have_) {
    have_ = 0;
    return SeekChunk::overflow;
  }
  std::memcpy(bytes_.data() + have_, chunk.data(), chunk.size());
  have_ += chunk.size();
  return have_ == bytes_.size() ? SeekChunk::complete : SeekChunk::need_more;
}

bool SeekFrameParser::parse(std::span<const std::uint8_t> frame, SeekFrameInfo& info) {
  if (frame.size() != bytes_.size()) return false;
  for (std::size_t i = 0; i < words_.size(); ++i)
    words_[i] = static_cast<std::uint16_t>(frame[2 * i] | (frame[2 * i + 1] << 8));
  SeekFrameInfo out;
  out.type = words_[model_.type_word];
  out.counter = words_[model_.counter_word];
  out.kind = seek_frame_kind(out.type);
  info = out;
  return true;
}

}  // namespace bolo::hal
