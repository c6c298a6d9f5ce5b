// NumPy .npy: header parsing (versions 1.0/2.0/3.0), frame-wise reading, stack writing.

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <limits>

#include "bolo/recording/recording.hpp"
#include "detail.hpp"

namespace bolo::rec {
namespace {

using detail::fail;
using detail::fail_frame;

constexpr std::string_view kMagic{"\x93NUMPY", 6};

std::string_view descr_of(DType dtype) { return dtype == DType::u2 ? "<u2" : "<f4"; }
std::string_view type_name(DType dtype) { return dtype == DType::u2 ? "uint16" : "float32"; }
std::uint64_t item_size(DType dtype) { return dtype == DType::u2 ? 2 : 4; }

// What the header says, before any check against what the caller wants.
struct RawHeader {
  std::string descr;
  bool fortran_order = false;
  std::vector<std::uint64_t> shape;
  std::uint64_t data_offset = 0;
  std::uint64_t file_size = 0;
};

// The header is a Python dict literal, e.g.
//   {'descr': '<u2', 'fortran_order': False, 'shape': (160, 120, 160), }
class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::filesystem::path& file)
      : s_(text), file_(file) {}

  void parse(RawHeader& out) {
    bool have_descr = false, have_order = false, have_shape = false;
    expect('{', "at the start of the header");
    for (;;) {
      if (eat('}')) break;
      const std::string key = string_literal("a key");
      expect(':', "after key '" + key + "'");
      if (key == "descr") {
        if (have_descr) bad("key 'descr' given twice");
        skip_ws();
        if (i_ < s_.size() && (s_[i_] == '[' || s_[i_] == '('))
          fail(file_, "dtype is a structured (record) dtype, expected a plain '<u2' or '<f4'");
        out.descr = string_literal("the value of 'descr'");
        have_descr = true;
      } else if (key == "fortran_order") {
        if (have_order) bad("key 'fortran_order' given twice");
        const std::string word = identifier();
        if (word == "True") out.fortran_order = true;
        else if (word == "False") out.fortran_order = false;
        else bad("'fortran_order' must be True or False");
        have_order = true;
      } else if (key == "shape") {
        if (have_shape) bad("key 'shape' given twice");
        out.shape = tuple();
        have_shape = true;
      } else {
        bad("unexpected key '" + key + "'");
      }
      if (eat(',')) continue;
      expect('}', "after the value of '" + key + "'");
      break;
    }
    skip_ws();
    if (i_ != s_.size()) bad("unexpected text after the dictionary");
    if (!have_descr) bad("key 'descr' missing");
    if (!have_order) bad("key 'fortran_order' missing");
    if (!have_shape) bad("key 'shape' missing");
  }

 private:
  [[noreturn]] void bad(const std::string& what) {
    fail(file_, "bad .npy header: " + what + " (header text offset " + std::to_string(i_) + ")");
  }
  void skip_ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r'))
      ++i_;
  }
  bool eat(char c) {
    skip_ws();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void expect(char c, const std::string& where) {
    if (!eat(c)) bad(std::string("expected '") + c + "' " + where);
  }
  std::string string_literal(const std::string& what) {
    skip_ws();
    if (i_ >= s_.size() || (s_[i_] != '\'' && s_[i_] != '"')) bad("expected a quoted string as " + what);
    const char quote = s_[i_++];
    std::string value;
    while (i_ < s_.size() && s_[i_] != quote) {
      if (s_[i_] == '\\' && i_ + 1 < s_.size()) ++i_;
      value += s_[i_++];
    }
    if (i_ >= s_.size()) bad("unterminated string");
    ++i_;
    return value;
  }
  std::string identifier() {
    skip_ws();
    const std::size_t start = i_;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) ++i_;
    return std::string(s_.substr(start, i_ - start));
  }
  std::vector<std::uint64_t> tuple() {
    std::vector<std::uint64_t> values;
    expect('(', "to open the value of 'shape'");
    for (;;) {
      if (eat(')')) break;
      skip_ws();
      std::uint64_t value = 0;
      const char* first = s_.data() + i_;
      const char* last = s_.data() + s_.size();
      const auto [ptr, ec] = std::from_chars(first, last, value);
      if (ec == std::errc::result_out_of_range) bad("shape entry out of range");
      if (ec != std::errc() || ptr == first) bad("'shape' must be a tuple of non-negative integers");
      i_ += static_cast<std::size_t>(ptr - first);
      if (i_ < s_.size() && (s_[i_] == 'L' || s_[i_] == 'l')) ++i_;  // Python 2 long
      values.push_back(value);
      if (eat(',')) continue;
      expect(')', "to close the value of 'shape'");
      break;
    }
    return values;
  }

  std::string_view s_;
  std::size_t i_ = 0;
  const std::filesystem::path& file_;
};

RawHeader parse_raw(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, std::string("cannot open: ") + std::strerror(errno));
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(file, ec);
  if (ec) fail(file, "cannot get the file size: " + ec.message());

  std::array<char, 12> prefix{};
  in.read(prefix.data(), 8);
  if (in.gcount() < 6 || std::string_view(prefix.data(), 6) != kMagic)
    fail(file, "not a .npy file (bad magic)");
  if (in.gcount() < 8) fail(file, "truncated: the file ends inside the .npy preamble");
  const auto major = static_cast<unsigned char>(prefix[6]);
  const auto minor = static_cast<unsigned char>(prefix[7]);
  if (major < 1 || major > 3 || minor != 0)
    fail(file, "unsupported .npy format version " + std::to_string(major) + "." +
                   std::to_string(minor) + " (expected 1.0, 2.0 or 3.0)");
  const std::size_t length_bytes = major == 1 ? 2 : 4;
  in.read(prefix.data() + 8, static_cast<std::streamsize>(length_bytes));
  if (static_cast<std::size_t>(in.gcount()) != length_bytes)
    fail(file, "truncated: the file ends inside the .npy preamble");
  std::uint64_t header_len = 0;
  for (std::size_t i = 0; i < length_bytes; ++i)
    header_len |= std::uint64_t{static_cast<unsigned char>(prefix[8 + i])} << (8 * i);

  RawHeader raw;
  raw.data_offset = 8 + length_bytes + header_len;
  raw.file_size = size;
  if (raw.data_offset > size)
    fail(file, "truncated: the header is " + std::to_string(header_len) +
                   " bytes long but the file has " + std::to_string(size) + " bytes");
  std::string text(header_len, '\0');
  in.read(text.data(), static_cast<std::streamsize>(header_len));
  if (static_cast<std::uint64_t>(in.gcount()) != header_len) fail(file, "read failed in the header");
  HeaderParser(text, file).parse(raw);
  if (raw.fortran_order) fail(file, "fortran_order is True, expected C order (False)");
  return raw;
}

void check_length(const std::filesystem::path& file, const RawHeader& raw, DType dtype) {
  std::uint64_t bytes = item_size(dtype);
  for (std::uint64_t dim : raw.shape) {
    if (dim != 0 && bytes > std::numeric_limits<std::uint64_t>::max() / dim)
      fail(file, "shape " + detail::shape_string(raw.shape) + " is too large");
    bytes *= dim;
  }
  const std::uint64_t available = raw.file_size - raw.data_offset;
  if (available >= bytes) return;
  std::string declared;
  if (raw.shape.size() == 3)
    declared = std::to_string(raw.shape[0]) + " frames of " +
               detail::size_string(raw.shape[1], raw.shape[2]) + " " +
               std::string(type_name(dtype));
  else
    declared = "shape " + detail::shape_string(raw.shape) + " of " + std::string(type_name(dtype));
  fail(file, "truncated: header declares " + declared + " (" + std::to_string(bytes) +
                 " bytes) but the file has " + std::to_string(available) + " bytes of data");
}

std::string header_dict(DType dtype, std::uint64_t n, std::uint64_t height, std::uint64_t width) {
  return "{'descr': '" + std::string(descr_of(dtype)) + "', 'fortran_order': False, 'shape': (" +
         std::to_string(n) + ", " + std::to_string(height) + ", " + std::to_string(width) + "), }";
}

// A version 1.0 header: magic, version, length, then the dict padded with spaces and ended by a
// newline so that the data starts at a multiple of 64 bytes, with room for a dict of
// `room_for` characters.
std::string version1_header(std::string dict, std::size_t room_for) {
  const std::size_t total = (10 + room_for + 1 + 63) / 64 * 64;
  const std::size_t header_len = total - 10;
  dict.resize(header_len - 1, ' ');
  dict += '\n';
  std::string bytes(kMagic);
  bytes += '\x01';
  bytes += '\x00';
  bytes += static_cast<char>(header_len & 0xff);
  bytes += static_cast<char>((header_len >> 8) & 0xff);
  return bytes + dict;
}

// The header of a frame stack, with room for any N (the frame count is rewritten as frames
// are appended).
std::string header_bytes(DType dtype, std::uint64_t n, std::uint64_t height, std::uint64_t width) {
  const std::size_t widest = header_dict(dtype, std::numeric_limits<std::uint64_t>::max(), height, width).size();
  return version1_header(header_dict(dtype, n, height, width), widest);
}

}  // namespace

std::string encode_npy_f4(const std::vector<std::uint64_t>& shape, std::span<const float> values) {
  std::uint64_t count = 1;
  std::string dims;
  for (std::uint64_t d : shape) {
    count *= d;
    dims += std::to_string(d) + ", ";
  }
  // "(3, 4)", but "(5,)" for one axis as Python writes a one-element tuple
  if (!dims.empty()) dims.resize(dims.size() - (shape.size() == 1 ? 1 : 2));
  if (count != values.size())
    throw Error("encode_npy_f4: shape holds " + std::to_string(count) + " values, got " +
                std::to_string(values.size()));
  const std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + dims + "), }";
  std::string bytes = version1_header(dict, dict.size());
  for (float v : values) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    for (int b = 0; b < 4; ++b) bytes += static_cast<char>((u >> (8 * b)) & 0xff);  // little-endian
  }
  return bytes;
}

NpyHeader read_npy_header(const std::filesystem::path& file) {
  const RawHeader raw = parse_raw(file);
  NpyHeader header;
  if (raw.descr == "<u2") header.dtype = DType::u2;
  else if (raw.descr == "<f4") header.dtype = DType::f4;
  else fail(file, "dtype '" + raw.descr + "' not supported (expected '<u2' or '<f4')");
  check_length(file, raw, header.dtype);
  header.shape = raw.shape;
  header.data_offset = raw.data_offset;
  return header;
}

// ---------------------------------------------------------------------------------------------

NpyFrameReader::NpyFrameReader(const std::filesystem::path& file, DType expected) : path_(file) {
  const RawHeader raw = parse_raw(file);
  if (raw.descr != descr_of(expected))
    fail(file, "dtype '" + raw.descr + "', expected '" + std::string(descr_of(expected)) + "'");
  if (raw.shape.size() != 3)
    fail(file, "shape " + detail::shape_string(raw.shape) + " is not a stack of frames (N, H, W)");
  // An empty frame holds no data, so check_length cannot bound its other side: (1, 0, 10^16)
  // "fits" in any file and then asks every reader for a row of 10^16 pixels.
  if (raw.shape[1] == 0 || raw.shape[2] == 0)
    fail(file, "frame size " + detail::size_string(raw.shape[1], raw.shape[2]) + " is empty");
  check_length(file, raw, expected);
  header_.dtype = expected;
  header_.shape = raw.shape;
  header_.data_offset = raw.data_offset;
  in_.open(file, std::ios::binary);
  if (!in_) fail(file, std::string("cannot open: ") + std::strerror(errno));
}

namespace {

void check_request(const std::filesystem::path& file, const NpyFrameReader& reader,
                   std::uint64_t index, DType wanted, std::size_t out_size, std::uint64_t expected_size) {
  if (reader.header().dtype != wanted)
    fail(file, "read as " + std::string(type_name(wanted)) + " but the file is '" +
                   std::string(descr_of(reader.header().dtype)) + "'");
  if (index >= reader.frames())
    fail_frame(file, index, {}, "out of range (" + std::to_string(reader.frames()) + " frames)");
  if (out_size != expected_size)
    fail_frame(file, index, {}, "output buffer holds " + std::to_string(out_size) +
                                    " values, expected " + std::to_string(expected_size));
}

void read_at(std::ifstream& in, const std::filesystem::path& file, std::uint64_t frame,
             std::uint64_t offset, void* out, std::uint64_t bytes) {
  in.clear();
  in.seekg(static_cast<std::streamoff>(offset));
  in.read(static_cast<char*>(out), static_cast<std::streamsize>(bytes));
  if (!in || static_cast<std::uint64_t>(in.gcount()) != bytes)
    fail_frame(file, frame, {}, "read failed (was the file changed while open?)");
}

}  // namespace

void NpyFrameReader::read_frame(std::uint64_t index, std::span<std::uint16_t> out) {
  const std::uint64_t pixels = height() * width();
  check_request(path_, *this, index, DType::u2, out.size(), pixels);
  read_at(in_, path_, index, header_.data_offset + index * pixels * 2, out.data(), pixels * 2);
  if constexpr (detail::kBigEndianHost)
    for (std::uint16_t& v : out) v = detail::byteswap16(v);
}

void NpyFrameReader::read_frame(std::uint64_t index, std::span<float> out) {
  const std::uint64_t pixels = height() * width();
  check_request(path_, *this, index, DType::f4, out.size(), pixels);
  read_at(in_, path_, index, header_.data_offset + index * pixels * 4, out.data(), pixels * 4);
  if constexpr (detail::kBigEndianHost)
    for (float& v : out)
      v = std::bit_cast<float>(detail::byteswap32(std::bit_cast<std::uint32_t>(v)));
}

void NpyFrameReader::read_row(std::uint64_t frame, std::uint64_t row, std::span<std::uint16_t> out) {
  check_request(path_, *this, frame, DType::u2, out.size(), width());
  if (row >= height())
    fail_frame(path_, frame, {}, "row " + std::to_string(row) + " out of range (" +
                                     std::to_string(height()) + " rows)");
  const std::uint64_t offset = header_.data_offset + ((frame * height() + row) * width()) * 2;
  read_at(in_, path_, frame, offset, out.data(), width() * 2);
  if constexpr (detail::kBigEndianHost)
    for (std::uint16_t& v : out) v = detail::byteswap16(v);
}

// ---------------------------------------------------------------------------------------------

NpyStackWriter::NpyStackWriter(const std::filesystem::path& file, DType dtype,
                               std::uint64_t height, std::uint64_t width)
    : path_(file), dtype_(dtype), height_(height), width_(width) {
  if (height == 0 || width == 0)
    fail(file, "frame size " + detail::size_string(height, width) + " is empty");
  out_.open(file, std::ios::binary | std::ios::trunc);
  if (!out_) fail(file, std::string("cannot create: ") + std::strerror(errno));
  const std::string header = header_bytes(dtype_, 0, height_, width_);
  out_.write(header.data(), static_cast<std::streamsize>(header.size()));
  if (!out_) fail(file, "write failed");
}

namespace {

void check_append(const std::filesystem::path& file, bool finished, std::uint64_t frame,
                  std::size_t size, std::uint64_t height, std::uint64_t width) {
  if (finished) fail(file, "append after finish()");
  if (size != height * width)
    fail_frame(file, frame, {}, std::to_string(size) + " pixels, expected " +
                                    std::to_string(height * width) + " (" +
                                    detail::size_string(height, width) + ")");
}

}  // namespace

void NpyStackWriter::append(std::span<const std::uint16_t> frame) {
  check_append(path_, finished_, frames_, frame.size(), height_, width_);
  if (dtype_ == DType::f4) {
    // Widening to float32 is exact for every uint16 value.
    std::vector<float> values(frame.begin(), frame.end());
    append(std::span<const float>(values));
    return;
  }
  if constexpr (detail::kBigEndianHost) {
    std::vector<std::uint16_t> swapped(frame.begin(), frame.end());
    for (std::uint16_t& v : swapped) v = detail::byteswap16(v);
    out_.write(reinterpret_cast<const char*>(swapped.data()),
               static_cast<std::streamsize>(swapped.size() * 2));
  } else {
    out_.write(reinterpret_cast<const char*>(frame.data()),
               static_cast<std::streamsize>(frame.size() * 2));
  }
  if (!out_) fail_frame(path_, frames_, {}, "write failed");
  ++frames_;
}

void NpyStackWriter::append(std::span<const float> frame) {
  check_append(path_, finished_, frames_, frame.size(), height_, width_);
  if (dtype_ != DType::f4)
    fail(path_, "cannot append float32 frames to a '<u2' stack");
  if constexpr (detail::kBigEndianHost) {
    std::vector<std::uint32_t> swapped(frame.size());
    for (std::size_t i = 0; i < frame.size(); ++i)
      swapped[i] = detail::byteswap32(std::bit_cast<std::uint32_t>(frame[i]));
    out_.write(reinterpret_cast<const char*>(swapped.data()),
               static_cast<std::streamsize>(swapped.size() * 4));
  } else {
    out_.write(reinterpret_cast<const char*>(frame.data()),
               static_cast<std::streamsize>(frame.size() * 4));
  }
  if (!out_) fail_frame(path_, frames_, {}, "write failed");
  ++frames_;
}

void NpyStackWriter::finish() {
  if (finished_) fail(path_, "finish() called twice");
  finished_ = true;
  const std::string header = header_bytes(dtype_, frames_, height_, width_);
  out_.seekp(0);
  out_.write(header.data(), static_cast<std::streamsize>(header.size()));
  out_.close();
  if (!out_) fail(path_, "write failed while finishing");
}

}  // namespace bolo::rec
