// bolo correct on a recording made here (against the paper's formula) and on a shared real one.

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

constexpr double kTauH = 0.012, kTauC = 0.010;

cli::CorrectOptions options(const fs::path& in, const fs::path& out) {
  cli::CorrectOptions o;
  o.input = in;
  o.output = out;
  o.tau_h_s = kTauH;
  o.tau_c_s = kTauC;
  o.progress = false;
  return o;
}

// Expected frame i of the small recording from the formula, given per-frame timing functions.
template <typename Exposure, typename Readout>
std::vector<double> expected(std::uint64_t i, Exposure exposure, Readout readout) {
  const auto current = SmallRecording::frame(i);
  if (!SmallRecording::carries(i))
    return expected_frame(current, nullptr, kTauH, kTauC, exposure(i), 0.0);
  const auto previous = SmallRecording::frame(i - 1);
  return expected_frame(current, &previous, kTauH, kTauC, exposure(i), readout(i - 1));
}

// Checks every pixel of every frame of a uint16 output against the formula within 1 LSB of the
// rounded value.
template <typename Exposure, typename Readout>
void check_fixed_output(const fs::path& dir, Exposure exposure, Readout readout) {
  rec::Recording out(dir);
  REQUIRE(out.frame_count() == SmallRecording::kFrames);
  double worst = 0;
  for (std::uint64_t i = 0; i < out.frame_count(); ++i) {
    const auto got = read_u16_frame(out, i);
    const auto want = expected(i, exposure, readout);
    for (std::size_t p = 0; p < got.size(); ++p) worst = std::max(worst, std::abs(got[p] - std::round(want[p])));
  }
  INFO("worst |output - round(formula)| = " << worst);
  CHECK(worst <= 1.0);
}

}  // namespace

TEST_CASE("correct: uint16 output follows Eq. 6 frame by frame, per-frame timing from frames.csv", "[cli][correct]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  std::ostringstream out;
  REQUIRE(cli::run_correct(options(tmp / "rec", tmp / "out"), out) == 0);
  check_fixed_output(tmp / "out", SmallRecording::exposure_s, SmallRecording::readout_s);

  // Summary: 12 frames, 9 corrected, the three reasons named.
  const std::string summary = out.str();
  INFO(summary);
  CHECK(summary.find("12: 9 corrected") != std::string::npos);
  CHECK(summary.find("first_frame 1") != std::string::npos);
  CHECK(summary.find("ffc_event 1") != std::string::npos);
  CHECK(summary.find("timestamp_gap 1") != std::string::npos);

  // Metadata: rows copied, recording.json says what was done, camera.json copied.
  rec::Recording in(tmp / "rec"), result(tmp / "out");
  REQUIRE(result.rows().size() == in.rows().size());
  for (std::size_t i = 0; i < in.rows().size(); ++i) {
    CHECK(result.rows()[i].t_s == in.rows()[i].t_s);
    CHECK(result.rows()[i].exposure_s == in.rows()[i].exposure_s);
    CHECK(result.rows()[i].readout_s == in.rows()[i].readout_s);
    CHECK(result.rows()[i].ffc == in.rows()[i].ffc);
    CHECK(result.rows()[i].fpa_temp_c == in.rows()[i].fpa_temp_c);
  }
  CHECK(result.info().sensor == "test sensor");
  CHECK(result.info().bits == 14);
  CHECK(result.info().notes.find("tau_h = 0.012 s") != std::string::npos);
  CHECK(result.info().notes.find("tau_c = 0.01 s") != std::string::npos);
  CHECK(result.info().source.find("bolo correct") != std::string::npos);
  CHECK(result.info().extra.at("correction").at("tau_h_s") == kTauH);
  REQUIRE(result.camera().has_value());
  CHECK(*result.camera() == *in.camera());
}

TEST_CASE("correct: frames.csv timing wins over the flags, which fill the empty cells", "[cli][correct]") {
  TempDir tmp;
  // Frames 4 and 5 have empty exposure/readout cells; the flags fill those two only.
  SmallRecording::write(tmp / "rec", [](std::uint64_t i) { return i != 4 && i != 5; });
  const double flag_exposure = 0.009, flag_readout = 0.006;
  auto o = options(tmp / "rec", tmp / "out");
  o.exposure_s = flag_exposure;
  o.readout_s = flag_readout;
  std::ostringstream out;
  REQUIRE(cli::run_correct(o, out) == 0);
  const auto exposure = [&](std::uint64_t i) { return i == 4 || i == 5 ? flag_exposure : SmallRecording::exposure_s(i); };
  const auto readout = [&](std::uint64_t i) { return i == 4 || i == 5 ? flag_readout : SmallRecording::readout_s(i); };
  check_fixed_output(tmp / "out", exposure, readout);
  // OUT given with a trailing slash is the same folder.
  o.output = (tmp / "out2").string() + "/";
  REQUIRE(cli::run_correct(o, out) == 0);
  check_fixed_output(tmp / "out2", exposure, readout);
  CHECK(out.str().find("frames.csv for 10 frames, --exposure for 2") != std::string::npos);
  CHECK(out.str().find("frames.csv for 10 frames, --readout for 2") != std::string::npos);
}

TEST_CASE("correct: scene.npy and poses.tum come along", "[cli][correct]") {
  TempDir tmp;
  {
    SmallRecording::write(tmp / "base");
    rec::Recording base(tmp / "base");
    rec::RecordingWriter writer(tmp / "rec", base.info());
    for (std::uint64_t i = 0; i < base.frame_count(); ++i) {
      writer.append(read_u16_frame(base, i), base.rows()[i]);
      std::vector<float> scene(std::size_t{base.width()} * base.height(), 1000.0f + static_cast<float>(i));
      writer.append_scene(scene);
    }
    writer.add_file("poses.tum", "5.0 0 0 0 0 0 0 1\n");
    writer.commit();
  }
  std::ostringstream out;
  REQUIRE(cli::run_correct(options(tmp / "rec", tmp / "out"), out) == 0);
  rec::Recording result(tmp / "out");
  REQUIRE(result.has_scene());
  std::vector<float> scene(std::size_t{result.width()} * result.height());
  result.read_scene(11, scene);
  CHECK(scene.front() == 1011.0f);
  CHECK(read_text(tmp / "out" / "poses.tum") == "5.0 0 0 0 0 0 0 1\n");
  CHECK(read_text(tmp / "out" / "scene.npy") == read_text(tmp / "rec" / "scene.npy"));
}

TEST_CASE("correct --float: float32 frames from the reference, within 1 LSB of the fixed output", "[cli][correct]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  std::ostringstream out;
  REQUIRE(cli::run_correct(options(tmp / "rec", tmp / "fixed"), out) == 0);
  auto o = options(tmp / "rec", tmp / "float");
  o.float_output = true;
  REQUIRE(cli::run_correct(o, out) == 0);

  rec::NpyFrameReader floats(tmp / "float" / "frames.npy", rec::DType::f4);
  REQUIRE(floats.frames() == SmallRecording::kFrames);
  REQUIRE(floats.height() == SmallRecording::kHeight);
  REQUIRE(floats.width() == SmallRecording::kWidth);
  rec::Recording fixed(tmp / "fixed");
  std::vector<float> f(std::size_t{SmallRecording::kWidth} * SmallRecording::kHeight);
  double worst_formula = 0, worst_fixed = 0;
  for (std::uint64_t i = 0; i < floats.frames(); ++i) {
    floats.read_frame(i, f);
    const auto want = expected(i, SmallRecording::exposure_s, SmallRecording::readout_s);
    const auto fx = read_u16_frame(fixed, i);
    for (std::size_t p = 0; p < f.size(); ++p) {
      worst_formula = std::max(worst_formula, std::abs(f[p] - want[p]));
      worst_fixed = std::max(worst_fixed, std::abs(f[p] - static_cast<double>(fx[p])));
    }
  }
  CHECK(worst_formula <= 0.01);  // float32 rounding of values below 2^16
  CHECK(worst_fixed <= 1.0);
  // The rows and metadata come along as for uint16 output.
  CHECK(rec::read_frames_csv(tmp / "float" / "frames.csv").size() == SmallRecording::kFrames);
  CHECK(rec::read_recording_json(tmp / "float" / "recording.json").notes.find("float32") != std::string::npos);
}

TEST_CASE("correct --stats: one row per frame with the reason and the coefficients", "[cli][correct]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  auto o = options(tmp / "rec", tmp / "out");
  o.stats = tmp / "stats.csv";
  std::ostringstream out;
  REQUIRE(cli::run_correct(o, out) == 0);
  std::istringstream csv(read_text(tmp / "stats.csv"));
  std::string line;
  std::getline(csv, line);
  CHECK(line == "frame,carry_over,coefficient_status,gain,carry,saturated_low,saturated_high,bad_pixels_replaced");
  std::uint64_t i = 0;
  while (std::getline(csv, line)) {
    INFO(line);
    std::vector<std::string> cells;
    std::stringstream cs(line);
    for (std::string c; std::getline(cs, c, ',');) cells.push_back(c);
    REQUIRE(cells.size() == 8);
    CHECK(cells[0] == std::to_string(i));
    const char* reason = i == 0 ? "first_frame"
                         : i == SmallRecording::kFfcFrame ? "ffc_event"
                         : i == SmallRecording::kGapFrame ? "timestamp_gap"
                                                          : "applied";
    CHECK(cells[1] == reason);
    CHECK(cells[2] == "ok");
    const double g = 1.0 / (1.0 - std::exp(-SmallRecording::exposure_s(i) / kTauH));
    CHECK(std::stod(cells[3]) == Approx(g).epsilon(1e-6));
    const double carry = SmallRecording::carries(i) ? g * std::exp(-SmallRecording::readout_s(i - 1) / kTauC) : 0.0;
    CHECK(std::stod(cells[4]) == Approx(carry).epsilon(1e-6).margin(1e-9));
    ++i;
  }
  CHECK(i == SmallRecording::kFrames);
}

TEST_CASE("correct --bad-pixels: stuck pixels are replaced before the corrector", "[cli][correct]") {
  TempDir tmp;
  // The small recording, and a copy with pixel (5, 7) stuck at the 14-bit rail in every frame.
  SmallRecording::write(tmp / "clean");
  const std::size_t at = 7 * SmallRecording::kWidth + 5;
  {
    rec::Recording source(tmp / "clean");
    rec::RecordingWriter writer(tmp / "stuck", source.info());
    for (std::uint64_t i = 0; i < source.frame_count(); ++i) {
      auto f = read_u16_frame(source, i);
      f[at] = 0x3FFF;
      writer.append(f, source.rows()[i]);
    }
    writer.commit();
  }
  std::ostringstream out;
  REQUIRE(cli::run_correct(options(tmp / "clean", tmp / "clean-out"), out) == 0);
  auto o = options(tmp / "stuck", tmp / "stuck-out");
  o.bad_pixels = true;
  std::ostringstream summary;
  REQUIRE(cli::run_correct(o, summary) == 0);
  CHECK(summary.str().find("12 replaced, 0 unrepairable") != std::string::npos);
  REQUIRE(cli::run_correct(options(tmp / "stuck", tmp / "unrepaired-out"), out) == 0);
  // Everywhere else the output is that of the clean recording; at the stuck pixel it is close to
  // it (the mean of its neighbours), far closer than without --bad-pixels.
  rec::Recording clean(tmp / "clean-out"), fixed(tmp / "stuck-out"), unrepaired(tmp / "unrepaired-out");
  for (std::uint64_t i = 0; i < clean.frame_count(); ++i) {
    const auto want = read_u16_frame(clean, i), got = read_u16_frame(fixed, i);
    for (std::size_t p = 0; p < want.size(); ++p)
      if (p != at) REQUIRE(got[p] == want[p]);
    const int bad = read_u16_frame(unrepaired, i)[at];
    INFO("frame " << i << ": clean " << want[at] << ", repaired " << got[at] << ", unrepaired " << bad);
    CHECK(3 * std::abs(int{got[at]} - int{want[at]}) < std::abs(bad - int{want[at]}));
  }
}

TEST_CASE("correct: the shared lepton3-possum recording, uint16 and --float agree within 1 LSB", "[cli][correct][shared]") {
  const fs::path possum = shared_recording("lepton3-possum");
  if (possum.empty()) return;
  TempDir tmp;
  const auto run = [&](const std::string& out, bool as_float) {
    std::vector<std::string> args = {"correct", possum.string(), (tmp / out).string(), "--tau-h", "0.012",
                                     "--tau-c", "0.012", "--exposure", "0.01", "--readout", "0.1"};
    if (as_float) args.push_back("--float");
    return run_bolo(args);
  };
  const CliResult fixed = run("fixed", false);
  INFO(fixed.err);
  REQUIRE(fixed.code == 0);
  CHECK(fixed.out.find("160: 159 corrected") != std::string::npos);
  const CliResult floating = run("float", true);
  INFO(floating.err);
  REQUIRE(floating.code == 0);

  rec::Recording in(possum), out(tmp / "fixed");  // a valid recording in the shared format
  REQUIRE(out.frame_count() == in.frame_count());
  CHECK(out.width() == in.width());
  CHECK(out.height() == in.height());
  CHECK(out.info().units == in.info().units);
  rec::NpyFrameReader floats(tmp / "float" / "frames.npy", rec::DType::f4);
  REQUIRE(floats.frames() == in.frame_count());
  std::vector<float> f(std::size_t{in.width()} * in.height());
  double worst = 0;
  std::uint64_t changed = 0;
  for (std::uint64_t i = 0; i < in.frame_count(); ++i) {
    const auto fx = read_u16_frame(out, i);
    const auto raw = read_u16_frame(in, i);
    floats.read_frame(i, f);
    for (std::size_t p = 0; p < f.size(); ++p) {
      worst = std::max(worst, std::abs(f[p] - static_cast<double>(fx[p])));
      changed += fx[p] != raw[p];
    }
  }
  INFO("worst |float - fixed| = " << worst);
  CHECK(worst <= 1.0);
  CHECK(changed > 0);  // the correction did something
}
