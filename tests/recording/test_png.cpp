// PNG folders and PNG writing (libpng).

#include "rec_test_helpers.hpp"

using namespace bolo;
using bolo::test::contains;
using bolo::test::error_of;

namespace {

std::vector<std::uint16_t> pattern(std::uint32_t w, std::uint32_t h, std::uint32_t seed) {
  std::vector<std::uint16_t> v(std::size_t{w} * h);
  std::uint32_t x = seed * 2654435761u + 1;
  for (auto& p : v) {
    x = x * 1664525u + 1013904223u;
    p = static_cast<std::uint16_t>(x >> 16);
  }
  v[0] = 0;
  v[1] = 65535;
  v[2] = 0x1234;
  return v;
}

}  // namespace

TEST_CASE("png: 16-bit grayscale round trip and folder scan sorted by name", "[png]") {
  test::TempDir tmp;
  const auto a = pattern(7, 5, 1), b = pattern(7, 5, 2), c = pattern(7, 5, 3);
  rec::write_png16(tmp / "frame_0002.png", 7, 5, c);
  rec::write_png16(tmp / "frame_0000.png", 7, 5, a);
  rec::write_png16(tmp / "frame_0001.PNG", 7, 5, b);
  test::write_bytes(tmp / "notes.txt", "not a frame");
  CHECK(test::folder_entries(tmp.path()).size() == 4);  // no temporaries left

  const rec::PngFolder folder = rec::scan_png_folder(tmp.path());
  REQUIRE(folder.files.size() == 3);
  CHECK(folder.files[0].filename() == "frame_0000.png");
  CHECK(folder.files[1].filename() == "frame_0001.PNG");
  CHECK(folder.files[2].filename() == "frame_0002.png");
  CHECK(folder.width == 7);
  CHECK(folder.height == 5);
  std::vector<std::uint16_t> out(35);
  rec::read_png16(folder.files[0], 7, 5, out);
  CHECK(out == a);
  rec::read_png16(folder.files[2], 7, 5, out);
  CHECK(out == c);
  // PNG stores 16-bit samples big-endian: the first sample after the filter byte.
  // (Checked indirectly: 0x1234 came back as 0x1234 above; a byte-order slip would give 0x3412.)
  CHECK(out[2] == 0x1234);

  CHECK(contains(error_of([&] { rec::read_png16(folder.files[0], 5, 7, std::span<std::uint16_t>(out)); }),
                 "frame_0000.png: width 7, height 5, expected width 5, height 7"));
}

TEST_CASE("png: an 8-bit PNG in a 16-bit folder is refused, naming the file", "[png][bad-input]") {
  test::TempDir tmp;
  rec::write_png16(tmp / "a.png", 4, 3, pattern(4, 3, 1));
  std::vector<std::uint8_t> rgb(4 * 3 * 3, 200);
  rec::write_png_rgb8(tmp / "b.png", 4, 3, rgb);
  CHECK(error_of([&] { rec::scan_png_folder(tmp.path()); }) ==
        (tmp / "b.png").string() + ": 8-bit RGB PNG, expected 16-bit grayscale");
  std::vector<std::uint16_t> out(12);
  CHECK(contains(error_of([&] { rec::read_png16(tmp / "b.png", 4, 3, out); }), "b.png: 8-bit RGB PNG"));
}

TEST_CASE("png: frames of different sizes are refused, naming the file", "[png][bad-input]") {
  test::TempDir tmp;
  rec::write_png16(tmp / "a.png", 4, 3, pattern(4, 3, 1));
  rec::write_png16(tmp / "b.png", 3, 4, pattern(3, 4, 1));
  CHECK(error_of([&] { rec::scan_png_folder(tmp.path()); }) ==
        (tmp / "b.png").string() + ": width 3, height 4, but a.png has width 4, height 3");
  test::TempDir empty;
  CHECK(error_of([&] { rec::scan_png_folder(empty.path()); }) == empty.path().string() + ": no *.png files");
  CHECK(contains(error_of([&] { rec::scan_png_folder(empty / "absent"); }), "absent: not a folder"));
}

TEST_CASE("png: corrupt PNG files become an Error naming the file", "[png][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frame.png";
  rec::write_png16(file, 64, 48, pattern(64, 48, 7));
  const std::string good = test::read_bytes(file);
  std::vector<std::uint16_t> out(64 * 48);

  SECTION("truncated image data") {
    test::write_bytes(file, good.substr(0, good.size() / 2));
    CHECK(rec::scan_png_folder(tmp.path()).files.size() == 1);  // the header is intact
    const std::string msg = error_of([&] { rec::read_png16(file, 64, 48, out); });
    CHECK(msg.starts_with(file.string() + ": corrupt PNG: "));
  }
  SECTION("flipped byte in the image data (CRC error)") {
    std::string bad = good;
    bad[bad.size() / 2] = static_cast<char>(bad[bad.size() / 2] ^ 0x5a);
    test::write_bytes(file, bad);
    const std::string msg = error_of([&] { rec::read_png16(file, 64, 48, out); });
    CHECK(msg.starts_with(file.string() + ": corrupt PNG: "));
  }
  SECTION("truncated inside the header") {
    test::write_bytes(file, good.substr(0, 20));
    CHECK(error_of([&] { rec::scan_png_folder(tmp.path()); }).starts_with(file.string() + ": corrupt PNG: "));
  }
  SECTION("not a PNG at all") {
    test::write_bytes(file, "GIF89a and then some");
    CHECK(error_of([&] { rec::scan_png_folder(tmp.path()); }) == file.string() + ": not a PNG file (bad signature)");
    CHECK(error_of([&] { rec::read_png16(file, 64, 48, out); }) == file.string() + ": not a PNG file (bad signature)");
  }
}

TEST_CASE("png: writers check the buffer size", "[png][bad-input]") {
  test::TempDir tmp;
  std::vector<std::uint16_t> px(11);
  CHECK(contains(error_of([&] { rec::write_png16(tmp / "x.png", 4, 3, px); }), "x.png: buffer holds 11 values, expected 12"));
  std::vector<std::uint8_t> rgb(12);
  CHECK(contains(error_of([&] { rec::write_png_rgb8(tmp / "y.png", 4, 3, rgb); }), "expected 36"));
  CHECK(test::folder_entries(tmp.path()).empty());
}
