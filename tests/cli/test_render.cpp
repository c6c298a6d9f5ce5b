// bolo render: PNG views decoded back and checked pixel by pixel.

#include <catch2/catch.hpp>

#include <png.h>

#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

struct Image {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  const std::uint8_t* at(std::uint32_t x, std::uint32_t y) const { return rgb.data() + (std::size_t{y} * width + x) * 3; }
};

Image read_png(const fs::path& file) {
  // The file itself is 8-bit RGB (IHDR: bit depth at byte 24, colour type at 25).
  const std::string bytes = read_text(file);
  REQUIRE(bytes.size() > 26);
  CHECK(bytes[24] == 8);
  CHECK(bytes[25] == 2);
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  REQUIRE(png_image_begin_read_from_file(&image, file.c_str()) != 0);
  image.format = PNG_FORMAT_RGB;
  Image out{image.width, image.height, std::vector<std::uint8_t>(PNG_IMAGE_SIZE(image))};
  REQUIRE(png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr) != 0);
  return out;
}

std::uint8_t gray_of(double v, double lo, double hi) {
  const double t = std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
  return static_cast<std::uint8_t>(std::lround(t * 255.0));
}

std::string range_in(const std::string& summary) {
  const auto start = summary.find("range ");
  return start == std::string::npos ? "" : summary.substr(start);
}

}  // namespace

TEST_CASE("render --frame --range: gray levels follow the fixed range", "[cli][render]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const CliResult r = run_bolo({"render", (tmp / "rec").string(), (tmp / "f.png").string(), "--frame", "7",
                                "--range", "3000:8000"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const Image img = read_png(tmp / "f.png");
  REQUIRE(img.width == SmallRecording::kWidth);
  REQUIRE(img.height == SmallRecording::kHeight);
  const auto frame = SmallRecording::frame(7);
  for (std::uint32_t y = 0; y < img.height; ++y)
    for (std::uint32_t x = 0; x < img.width; ++x) {
      const std::uint8_t want = gray_of(frame[std::size_t{y} * img.width + x], 3000, 8000);
      REQUIRE(img.at(x, y)[0] == want);
      REQUIRE(img.at(x, y)[1] == want);
      REQUIRE(img.at(x, y)[2] == want);
    }
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec", "f.png"});
}

TEST_CASE("render: one default range for every frame, --agc gives each frame its own", "[cli][render]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const auto render = [&](const std::string& frame, bool agc) {
    std::vector<std::string> args = {"render", (tmp / "rec").string(), (tmp / ("f" + frame + ".png")).string(),
                                     "--frame", frame};
    if (agc) args.push_back("--agc");
    const CliResult r = run_bolo(args);
    INFO(r.err);
    REQUIRE(r.code == 0);
    return r.out;
  };
  const std::string a = render("0", false), b = render("11", false);
  CHECK(range_in(a) == range_in(b));
  CHECK(a.find("percentiles 1:99 over 12 of 12 frames") != std::string::npos);
  // Same range: a pixel with the same raw value renders the same in both frames (the corner
  // pixel, away from the moving square).
  const Image ia = read_png(tmp / "f0.png"), ib = read_png(tmp / "f11.png");
  if (SmallRecording::frame(0)[0] == SmallRecording::frame(11)[0]) CHECK(ia.at(0, 0)[0] == ib.at(0, 0)[0]);
  const std::string c = render("0", true);
  CHECK(c.find("--agc") != std::string::npos);
}

TEST_CASE("render --compare --scale: raw | corrected side by side", "[cli][render]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  REQUIRE(run_bolo({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "0.012",
                    "--tau-c", "0.012"}).code == 0);
  const CliResult r = run_bolo({"render", (tmp / "rec").string(), (tmp / "cmp.png").string(), "--frame", "4",
                                "--compare", (tmp / "out").string(), "--scale", "3", "--range", "0:20000"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const Image img = read_png(tmp / "cmp.png");
  const std::uint32_t panel = SmallRecording::kWidth * 3, gap = 3;
  REQUIRE(img.width == 2 * panel + gap);
  REQUIRE(img.height == SmallRecording::kHeight * 3);
  rec::Recording raw(tmp / "rec"), corrected(tmp / "out");
  const auto fr = read_u16_frame(raw, 4), fc = read_u16_frame(corrected, 4);
  for (std::uint32_t y = 0; y < SmallRecording::kHeight; ++y)
    for (std::uint32_t x = 0; x < SmallRecording::kWidth; ++x) {
      const std::size_t p = std::size_t{y} * SmallRecording::kWidth + x;
      // Every pixel is a 3x3 block; check its bottom-right corner.
      REQUIRE(img.at(x * 3 + 2, y * 3 + 2)[0] == gray_of(fr[p], 0, 20000));
      REQUIRE(img.at(panel + gap + x * 3 + 2, y * 3 + 2)[0] == gray_of(fc[p], 0, 20000));
    }
}

TEST_CASE("render --compare: one fixed range per recording by default, one shared with --same-range", "[cli][render]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  REQUIRE(run_bolo({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "0.012",
                    "--tau-c", "0.012"}).code == 0);
  const CliResult own = run_bolo({"render", (tmp / "rec").string(), (tmp / "a.png").string(), "--frame", "4",
                                  "--compare", (tmp / "out").string()});
  REQUIRE(own.code == 0);
  CHECK(own.out.find("per recording") != std::string::npos);
  const CliResult shared = run_bolo({"render", (tmp / "rec").string(), (tmp / "b.png").string(), "--frame", "4",
                                     "--compare", (tmp / "out").string(), "--same-range"});
  REQUIRE(shared.code == 0);
  CHECK(shared.out.find("one range for both recordings") != std::string::npos);
  // "range A .. B | C .. D (...)": one range per side, different ones unless --same-range.
  auto ranges = [](const std::string& text) {
    const auto at = text.find("; range ");
    const auto bar = text.find(" | ", at);
    const auto end = text.find(" (", bar);
    return std::make_pair(text.substr(at + 8, bar - at - 8), text.substr(bar + 3, end - bar - 3));
  };
  const auto [own_a, own_b] = ranges(own.out);
  const auto [shared_a, shared_b] = ranges(shared.out);
  CHECK(own_a != own_b);
  CHECK(shared_a == shared_b);
  CHECK(read_text(tmp / "a.png") != read_text(tmp / "b.png"));
}

TEST_CASE("render --contact-sheet: evenly spaced tiles in columns, iron colormap, labels", "[cli][render]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const CliResult r = run_bolo({"render", (tmp / "rec").string(), (tmp / "sheet.png").string(), "--contact-sheet",
                                "--count", "6", "--columns", "4", "--colormap", "iron", "--labels"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("6 frames of 12 in 4 columns") != std::string::npos);
  const Image img = read_png(tmp / "sheet.png");
  CHECK(img.width == 4 * SmallRecording::kWidth + 3 * 4);   // tile gap 4 pixels at scale 1
  CHECK(img.height == 2 * SmallRecording::kHeight + 4);
  bool coloured = false;
  for (std::size_t i = 0; i + 2 < img.rgb.size(); i += 3) coloured |= img.rgb[i] != img.rgb[i + 2];
  CHECK(coloured);
  // Default count 16 on 12 frames: all of them.
  const CliResult all = run_bolo({"render", (tmp / "rec").string(), (tmp / "all.png").string(), "--contact-sheet"});
  REQUIRE(all.code == 0);
  CHECK(all.out.find("12 frames of 12 in 4 columns") != std::string::npos);
}

TEST_CASE("render reads the float32 output of correct --float", "[cli][render]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  REQUIRE(run_bolo({"correct", (tmp / "rec").string(), (tmp / "f").string(), "--tau-h", "0.012", "--tau-c",
                    "0.012", "--float"}).code == 0);
  const CliResult r = run_bolo({"render", (tmp / "f").string(), (tmp / "f.png").string(), "--compare",
                                (tmp / "rec").string(), "--frame", "2"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(read_png(tmp / "f.png").width == 2 * SmallRecording::kWidth + 2);
  const CliResult info = run_bolo({"info", (tmp / "f").string()});
  REQUIRE(info.code == 0);
  CHECK(info.out.find("float32") != std::string::npos);
}

TEST_CASE("render refuses negative numbers for unsigned options", "[cli][render][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
           {"--frame", "-1"}, {"--count", "-2"}, {"--scale", "-3"}, {"--columns", "-4"}}) {
    std::vector<std::string> args = {"render", (tmp / "rec").string(), (tmp / "x.png").string(), flag, value};
    if (flag != "--frame") args.push_back("--contact-sheet");
    const CliResult r = run_bolo(args);
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.find(flag) != std::string::npos);
    CHECK(!fs::exists(tmp / "x.png"));
  }
}
