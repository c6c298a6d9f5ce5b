#pragma once
// Helpers for the CLI tests: a small recording made at test time, the command line run
// in-process, the paper's formula for expected frames, and folder listings for "nothing left
// behind" checks.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../test_support.hpp"
#include "bolo/commands.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::test {

namespace fs = std::filesystem;

// The test recording: 24x16, 12 frames, 14-bit counts, per-frame exposure/readout, an FFC event
// before frame 6, a time gap between frames 9 and 10 (3 periods), frame 3 a copy of frame 2.
struct SmallRecording {
  static constexpr std::uint32_t kWidth = 24, kHeight = 16, kFrames = 12;
  static constexpr double kPeriod = 0.1;
  static constexpr std::uint64_t kFfcFrame = 6, kGapFrame = 10, kDuplicateFrame = 3;

  static double t_s(std::uint64_t i) { return 5.0 + kPeriod * static_cast<double>(i) + (i >= kGapFrame ? 2 * kPeriod : 0.0); }
  static double exposure_s(std::uint64_t i) { return 0.008 + 0.0005 * static_cast<double>(i % 3); }
  static double readout_s(std::uint64_t i) { return 0.004 + 0.001 * static_cast<double>(i % 4); }

  static std::vector<std::uint16_t> frame(std::uint64_t i) {
    if (i == kDuplicateFrame) i = kDuplicateFrame - 1;
    std::vector<std::uint16_t> pixels(std::size_t{kWidth} * kHeight);
    for (std::uint32_t y = 0; y < kHeight; ++y)
      for (std::uint32_t x = 0; x < kWidth; ++x) {
        // A warm background with a gradient and a hot square moving right: ghosting material.
        double v = 3000.0 + 40.0 * x + 25.0 * y + 7.0 * static_cast<double>((x * 31 + y * 17 + i * 13) % 11);
        const double cx = 3.0 + 1.5 * static_cast<double>(i);
        if (std::abs(x - cx) < 3 && y >= 5 && y < 11) v += 2500.0;
        pixels[std::size_t{y} * kWidth + x] = static_cast<std::uint16_t>(v);
      }
    return pixels;
  }

  static rec::FrameRow row(std::uint64_t i, bool timing = true) {
    rec::FrameRow r;
    r.index = i;
    r.t_s = t_s(i);
    if (timing) {
      r.exposure_s = exposure_s(i);
      r.readout_s = readout_s(i);
    }
    r.ffc = i == kFfcFrame;
    r.fpa_temp_c = 30.0 + 0.01 * static_cast<double>(i);
    return r;
  }

  // Writes the recording; `timing_for(i)` false leaves frame i's exposure/readout cells empty.
  template <typename TimingFor>
  static void write(const fs::path& dir, TimingFor timing_for) {
    rec::RecordingInfo info;
    info.sensor = "test sensor";
    info.width = kWidth;
    info.height = kHeight;
    info.bits = 14;
    info.fps = 1.0 / kPeriod;
    info.units = rec::Units::counts;
    info.source = "tests/cli";
    info.notes = "made by the test";
    rec::RecordingWriter writer(dir, info);
    for (std::uint64_t i = 0; i < kFrames; ++i) writer.append(frame(i), row(i, timing_for(i)));
    writer.set_camera({{"model", "pinhole"}, {"fx", 30.0}, {"fy", 30.0}, {"cx", 11.5}, {"cy", 7.5},
                       {"k1", 0}, {"k2", 0}, {"p1", 0}, {"p2", 0}});
    writer.commit();
  }
  static void write(const fs::path& dir) {
    write(dir, [](std::uint64_t) { return true; });
  }

  // Whether the corrector has a usable predecessor for frame i.
  static bool carries(std::uint64_t i) { return i != 0 && i != kFfcFrame && i != kGapFrame; }
};

// The paper's Eq. 6 in double precision, clamped to [0, 65535], not rounded.
inline std::vector<double> expected_frame(const std::vector<std::uint16_t>& current,
                                          const std::vector<std::uint16_t>* previous,
                                          double tau_h, double tau_c, double exposure,
                                          double previous_readout) {
  const double g = 1.0 / (1.0 - std::exp(-exposure / tau_h));
  const double a = previous ? std::exp(-previous_readout / tau_c) : 0.0;
  std::vector<double> out(current.size());
  for (std::size_t p = 0; p < current.size(); ++p) {
    const double prev = previous ? (*previous)[p] : 0.0;
    out[p] = std::clamp((current[p] - a * prev) * g, 0.0, 65535.0);
  }
  return out;
}

// The whole command line, in-process.
struct CliResult {
  int code = -1;
  std::string out, err;
};
inline CliResult run_bolo(std::vector<std::string> args) {
  args.insert(args.begin(), "bolo");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  CliResult r;
  r.code = cli::run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  r.out = out.str();
  r.err = err.str();
  return r;
}

// Every entry of a folder (hidden ones included), by name.
// Runs the command line and checks the shape of a refusal (exit 2, one `bolo: error:` line on
// stderr, nothing on stdout); returns stderr.
inline std::string refused(const std::vector<std::string>& args) {
  const CliResult r = run_bolo(args);
  INFO("args:" << [&] {
    std::string s;
    for (const auto& a : args) s += " '" + a + "'";
    return s;
  }() << "\nstdout: " << r.out << "\nstderr: " << r.err);
  CHECK(r.code == 2);
  CHECK(r.err.rfind("bolo: error: ", 0) == 0);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);  // one line
  CHECK(r.out.empty());
  return r.err;
}

inline std::vector<std::string> correct_args(const TempDir& tmp, const std::string& in = "rec", const std::string& out = "out") {
  return {"correct", (tmp / in).string(), (tmp / out).string(), "--tau-h", "0.012", "--tau-c", "0.012"};
}

inline std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

inline std::set<std::string> entries(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

inline std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::vector<std::uint16_t> read_u16_frame(rec::Recording& r, std::uint64_t i) {
  std::vector<std::uint16_t> f(std::size_t{r.width()} * r.height());
  r.read_frame(i, f);
  return f;
}

}  // namespace bolo::test
