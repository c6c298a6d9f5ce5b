#pragma once
// Helpers for the recording tests: capture an Error's message, build small (broken) fixtures.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "../test_support.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::test {

// The message of the bolo::rec::Error that `f` throws; fails the test if it throws nothing or
// something else.
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const rec::Error& e) {
    const std::string message = e.what();
    INFO("message: " << message);
    CHECK(message.find('\n') == std::string::npos);  // one line
    return message;
  } catch (const std::exception& e) {
    FAIL("expected bolo::rec::Error, got another exception: " << e.what());
  }
  FAIL("expected bolo::rec::Error, nothing was thrown");
  return {};
}

inline void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  REQUIRE(out.good());
}

inline std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  REQUIRE(in.good());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A hand-written .npy: `dict` is the header dictionary text, `data` the raw array bytes.
inline std::string npy_bytes(const std::string& dict, const std::string& data, int major = 1) {
  std::string header = dict;
  const std::size_t preamble = major == 1 ? 10 : 12;
  while ((preamble + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string out = "\x93NUMPY";
  out += static_cast<char>(major);
  out += '\0';
  const std::size_t n = header.size();
  out += static_cast<char>(n & 0xff);
  out += static_cast<char>((n >> 8) & 0xff);
  if (major != 1) {
    out += static_cast<char>((n >> 16) & 0xff);
    out += static_cast<char>((n >> 24) & 0xff);
  }
  return out + header + data;
}

// Little-endian bytes of values.
inline std::string le_u16(const std::vector<std::uint16_t>& values) {
  std::string out;
  for (std::uint16_t v : values) {
    out += static_cast<char>(v & 0xff);
    out += static_cast<char>(v >> 8);
  }
  return out;
}
inline std::string le_f32(const std::vector<float>& values) {
  std::string out;
  for (float f : values) {
    std::uint32_t v = 0;
    std::memcpy(&v, &f, 4);
    for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
  }
  return out;
}

// Pixel value of a fixture recording: distinct per frame and pixel.
inline std::uint16_t fixture_value(std::uint64_t frame, std::uint64_t pixel) {
  return static_cast<std::uint16_t>(1000 + 100 * frame + pixel);
}

inline rec::RecordingInfo fixture_info(std::uint32_t height = 3, std::uint32_t width = 5) {
  rec::RecordingInfo info;
  info.sensor = "test sensor";
  info.width = width;
  info.height = height;
  info.bits = 14;
  info.fps = 10.0;
  info.source = "bolo tests";
  return info;
}

inline rec::FrameRow fixture_row(std::uint64_t frame) {
  rec::FrameRow row;
  row.index = frame;
  row.t_s = 0.1 * static_cast<double>(frame);
  row.exposure_s = 0.01;
  row.readout_s = 0.02;
  row.ffc = frame == 2;
  row.fpa_temp_c = 30.5;
  row.housing_temp_c = 31.25;
  return row;
}

// A valid recording (frames x 3 x 5) at `dir`, written with RecordingWriter.
inline void make_fixture(const std::filesystem::path& dir, std::uint64_t frames = 4) {
  const rec::RecordingInfo info = fixture_info();
  rec::RecordingWriter writer(dir, info);
  std::vector<std::uint16_t> frame(std::size_t{info.width} * info.height);
  for (std::uint64_t f = 0; f < frames; ++f) {
    for (std::size_t p = 0; p < frame.size(); ++p) frame[p] = fixture_value(f, p);
    writer.append(frame, fixture_row(f));
  }
  writer.commit();
}

// Replaces line `n` (0 = header) of a text file.
inline void replace_line(const std::filesystem::path& file, std::size_t n, const std::string& line) {
  std::istringstream in(read_bytes(file));
  std::string out, current;
  for (std::size_t i = 0; std::getline(in, current); ++i) out += (i == n ? line : current) + "\n";
  write_bytes(file, out);
}

inline std::vector<std::string> folder_entries(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace bolo::test
