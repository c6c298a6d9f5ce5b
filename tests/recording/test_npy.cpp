// .npy reading and writing.

#include "rec_test_helpers.hpp"

using namespace bolo;
using bolo::test::contains;
using bolo::test::error_of;

namespace {

std::vector<std::uint16_t> ramp(std::size_t n, std::uint16_t start) {
  std::vector<std::uint16_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint16_t>(start + i);
  return v;
}

}  // namespace

TEST_CASE("npy: uint16 stack round-trips frame by frame and row by row", "[npy]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.npy";
  {
    rec::NpyStackWriter writer(file, rec::DType::u2, 4, 5);
    writer.append(ramp(20, 0));
    writer.append(ramp(20, 65500));  // wraps: covers both bytes and 0xffff
    writer.append(ramp(20, 0x1234));
    CHECK(writer.frames() == 3);
    writer.finish();
  }
  const rec::NpyHeader header = rec::read_npy_header(file);
  CHECK(header.dtype == rec::DType::u2);
  CHECK(header.shape == std::vector<std::uint64_t>{3, 4, 5});
  CHECK(header.data_offset % 64 == 0);
  CHECK(std::filesystem::file_size(file) == header.data_offset + 3 * 20 * 2);

  rec::NpyFrameReader reader(file, rec::DType::u2);
  CHECK(reader.frames() == 3);
  CHECK(reader.height() == 4);
  CHECK(reader.width() == 5);
  std::vector<std::uint16_t> frame(20);
  reader.read_frame(1, frame);
  CHECK(frame == ramp(20, 65500));
  reader.read_frame(0, frame);
  CHECK(frame == ramp(20, 0));
  std::vector<std::uint16_t> row(5);
  reader.read_row(2, 3, row);
  CHECK(row == ramp(5, 0x1234 + 15));
  // Little-endian on disk, whatever the host.
  const std::string bytes = test::read_bytes(file);
  CHECK(static_cast<unsigned char>(bytes[header.data_offset + 2 * 20 * 2]) == 0x34);
  CHECK(static_cast<unsigned char>(bytes[header.data_offset + 2 * 20 * 2 + 1]) == 0x12);
}

TEST_CASE("npy: float32 stack round-trips and uint16 frames widen exactly", "[npy]") {
  test::TempDir tmp;
  const auto file = tmp / "scene.npy";
  const std::vector<float> a = {1.5f, -3.25f, 1e-30f, 65535.0f, 0.1f, 123456.789f};
  {
    rec::NpyStackWriter writer(file, rec::DType::f4, 2, 3);
    writer.append(std::span<const float>(a));
    writer.append(std::span<const std::uint16_t>(ramp(6, 65530)));
    writer.finish();
  }
  CHECK(rec::read_npy_header(file).dtype == rec::DType::f4);
  rec::NpyFrameReader reader(file, rec::DType::f4);
  std::vector<float> frame(6);
  reader.read_frame(0, frame);
  CHECK(frame == a);
  reader.read_frame(1, frame);
  CHECK(frame == std::vector<float>{65530, 65531, 65532, 65533, 65534, 65535});
  const std::string msg = error_of([&] { reader.read_frame(0, std::span<std::uint16_t>()); });
  CHECK(contains(msg, "scene.npy"));
}

TEST_CASE("npy: the header has room for a 20-digit frame count", "[npy]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.npy";
  rec::NpyStackWriter writer(file, rec::DType::u2, 120, 160);
  writer.append(std::vector<std::uint16_t>(120 * 160, 7));
  writer.finish();
  const std::string bytes = test::read_bytes(file);
  const rec::NpyHeader header = rec::read_npy_header(file);
  REQUIRE(header.data_offset % 64 == 0);
  const std::string text = bytes.substr(10, header.data_offset - 10);
  CHECK(text.back() == '\n');
  const std::size_t close = text.find('}');
  REQUIRE(close != std::string::npos);
  // Shape "(1, ...)" is 1 digit; the padding must leave at least 19 more.
  CHECK(text.size() - 1 - (close + 1) >= 19);
  CHECK(bytes[6] == 1);
  CHECK(bytes[7] == 0);
}

TEST_CASE("npy: hand-written headers of versions 1.0, 2.0, 3.0 with keys in any order", "[npy]") {
  test::TempDir tmp;
  const std::string data = test::le_u16({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
  const std::vector<std::string> dicts = {
      "{'descr': '<u2', 'fortran_order': False, 'shape': (2, 2, 3), }",
      "{'shape': (2, 2, 3), 'descr': '<u2', 'fortran_order': False}",
      "{\"fortran_order\": False, \"shape\": (2,2,3), \"descr\": \"<u2\"}",
      "{'descr':'<u2','fortran_order':False,'shape':(2L, 2L, 3L),}",
  };
  for (int major = 1; major <= 3; ++major) {
    for (const std::string& dict : dicts) {
      INFO("version " << major << ".0, header " << dict);
      const auto file = tmp / ("v" + std::to_string(major) + ".npy");
      test::write_bytes(file, test::npy_bytes(dict, data, major));
      const rec::NpyHeader header = rec::read_npy_header(file);
      CHECK(header.shape == std::vector<std::uint64_t>{2, 2, 3});
      rec::NpyFrameReader reader(file, rec::DType::u2);
      std::vector<std::uint16_t> frame(6);
      reader.read_frame(1, frame);
      CHECK(frame == std::vector<std::uint16_t>{7, 8, 9, 10, 11, 12});
    }
  }
  // Other shapes are fine for read_npy_header (not for a frame reader).
  const auto vec = tmp / "vector.npy";
  test::write_bytes(vec, test::npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (3,), }",
                                         test::le_f32({1, 2, 3})));
  CHECK(rec::read_npy_header(vec).shape == std::vector<std::uint64_t>{3});
  const std::string msg = error_of([&] { rec::NpyFrameReader(vec, rec::DType::f4); });
  CHECK(contains(msg, "vector.npy: shape (3,) is not a stack of frames (N, H, W)"));
}

TEST_CASE("npy: truncated data is an error naming the file and both sizes", "[npy][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.npy";
  {
    rec::NpyStackWriter writer(file, rec::DType::u2, 120, 160);
    for (int i = 0; i < 160; ++i) writer.append(std::vector<std::uint16_t>(120 * 160, 1));
    writer.finish();
  }
  std::filesystem::resize_file(file, 128 + 4000000);
  const std::string expected = file.string() +
                               ": truncated: header declares 160 frames of 120x160 uint16 (6144000 "
                               "bytes) but the file has 4000000 bytes of data";
  CHECK(error_of([&] { rec::read_npy_header(file); }) == expected);
  CHECK(error_of([&] { rec::NpyFrameReader(file, rec::DType::u2); }) == expected);
}

TEST_CASE("npy: a file that is not .npy is refused", "[npy][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.npy";
  test::write_bytes(file, "index,t_s\n0,0.0\n");
  CHECK(error_of([&] { rec::read_npy_header(file); }) == file.string() + ": not a .npy file (bad magic)");
  test::write_bytes(file, "");
  CHECK(error_of([&] { rec::read_npy_header(file); }) == file.string() + ": not a .npy file (bad magic)");
  const std::string missing = error_of([&] { rec::read_npy_header(tmp / "absent.npy"); });
  CHECK(contains(missing, "absent.npy: cannot open"));
}

TEST_CASE("npy: wrong dtype is refused with the dtype named", "[npy][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.npy";
  const std::string shape = "'fortran_order': False, 'shape': (1, 2, 2), }";
  test::write_bytes(file, test::npy_bytes("{'descr': '<f4', " + shape, test::le_f32({1, 2, 3, 4})));
  CHECK(error_of([&] { rec::NpyFrameReader(file, rec::DType::u2); }) ==
        file.string() + ": dtype '<f4', expected '<u2'");

  test::write_bytes(file, test::npy_bytes("{'descr': '>u2', " + shape, std::string(8, '\0')));
  CHECK(error_of([&] { rec::NpyFrameReader(file, rec::DType::u2); }) ==
        file.string() + ": dtype '>u2', expected '<u2'");
  CHECK(contains(error_of([&] { rec::read_npy_header(file); }), "dtype '>u2' not supported"));

  test::write_bytes(file, test::npy_bytes("{'descr': '|u1', " + shape, std::string(4, '\0')));
  CHECK(contains(error_of([&] { rec::read_npy_header(file); }), "dtype '|u1' not supported"));

  test::write_bytes(file, test::npy_bytes("{'descr': [('a', '<u2')], " + shape, std::string(8, '\0')));
  CHECK(contains(error_of([&] { rec::read_npy_header(file); }), "structured"));
}

TEST_CASE("npy: malformed headers are refused", "[npy][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.npy";
  const std::string data(8, '\0');
  struct Case {
    std::string dict, expected;
  };
  const std::vector<Case> cases = {
      {"{'descr': '<u2', 'fortran_order': True, 'shape': (1, 2, 2), }", "fortran_order is True"},
      {"{'descr': '<u2', 'shape': (1, 2, 2), }", "key 'fortran_order' missing"},
      {"{'descr': '<u2', 'fortran_order': False, }", "key 'shape' missing"},
      {"{'descr': '<u2', 'fortran_order': False, 'shape': (1, 2, 2), 'x': 1}", "unexpected key 'x'"},
      {"{'descr': '<u2', 'fortran_order': False, 'shape': (1, -2, 2), }", "non-negative integers"},
      {"{'descr': '<u2', 'fortran_order': False, 'shape': (1, 2, 2) ", "expected '}'"},
      {"{'descr': '<u2' 'fortran_order': False, 'shape': (1, 2, 2)}", "expected '}'"},
      {"{'descr': '<u2', 'fortran_order': Maybe, 'shape': (1, 2, 2)}", "True or False"},
      {"{'descr': '<u2', 'descr': '<u2', 'fortran_order': False, 'shape': (1, 2, 2)}", "twice"},
      {"['descr', '<u2']", "expected '{'"},
  };
  for (const Case& c : cases) {
    INFO(c.dict);
    test::write_bytes(file, test::npy_bytes(c.dict, data));
    const std::string msg = error_of([&] { rec::read_npy_header(file); });
    CHECK(contains(msg, file.string() + ": "));
    CHECK(contains(msg, c.expected));
  }

  std::string v4 = test::npy_bytes("{'descr': '<u2', 'fortran_order': False, 'shape': (1, 2, 2), }", data);
  v4[6] = 4;
  test::write_bytes(file, v4);
  CHECK(contains(error_of([&] { rec::read_npy_header(file); }), "unsupported .npy format version 4.0"));

  std::string long_header = test::npy_bytes("{'descr': '<u2', 'fortran_order': False, 'shape': (1, 2, 2), }", "");
  long_header[8] = '\xff';
  long_header[9] = '\x7f';
  test::write_bytes(file, long_header);
  CHECK(contains(error_of([&] { rec::read_npy_header(file); }), "truncated: the header is 32767 bytes long"));
}

TEST_CASE("npy: a stack of empty frames is refused, however wide (found by fuzzing)", "[npy][bad-input]") {
  // An empty frame holds no data, so the file-size check alone would accept any other side.
  test::TempDir tmp;
  const auto file = tmp / "frames.npy";
  for (const std::string& shape : {"(1, 0, 51619111116191111)", "(3, 7, 0)", "(0, 0, 0)"}) {
    INFO(shape);
    test::write_bytes(file, test::npy_bytes("{'descr': '<u2', 'fortran_order': False, 'shape': " + shape + ", }", ""));
    const std::string msg = error_of([&] { rec::NpyFrameReader(file, rec::DType::u2); });
    CHECK(contains(msg, file.string() + ": frame size "));
    CHECK(contains(msg, " is empty"));
  }
  // Zero frames of a real size is an empty recording, not a malformed one.
  test::write_bytes(file, test::npy_bytes("{'descr': '<u2', 'fortran_order': False, 'shape': (0, 2, 3), }", ""));
  CHECK(rec::NpyFrameReader(file, rec::DType::u2).frames() == 0);
}

TEST_CASE("npy: out-of-range reads and wrong buffer sizes are errors", "[npy][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.npy";
  {
    rec::NpyStackWriter writer(file, rec::DType::u2, 2, 2);
    writer.append(ramp(4, 0));
    CHECK(contains(error_of([&] { writer.append(ramp(5, 0)); }), "frame 1: 5 pixels, expected 4 (2x2)"));
    CHECK(contains(error_of([&] { writer.append(std::vector<float>(4)); }), "float32"));
    writer.finish();
    CHECK(contains(error_of([&] { writer.append(ramp(4, 0)); }), "after finish"));
    CHECK(contains(error_of([&] { writer.finish(); }), "twice"));
  }
  rec::NpyFrameReader reader(file, rec::DType::u2);
  std::vector<std::uint16_t> frame(4);
  CHECK(error_of([&] { reader.read_frame(1, frame); }) ==
        file.string() + ": frame 1: out of range (1 frames)");
  std::vector<std::uint16_t> small(3);
  CHECK(contains(error_of([&] { reader.read_frame(0, small); }), "expected 4"));
  std::vector<std::uint16_t> row(2);
  CHECK(contains(error_of([&] { reader.read_row(0, 2, row); }), "row 2 out of range"));
  std::vector<float> floats(4);
  CHECK(contains(error_of([&] { reader.read_frame(0, floats); }), "read as float32"));
}

TEST_CASE("npy: encode_npy_f4 writes arrays of any shape that the reader accepts", "[npy]") {
  test::TempDir tmp;
  std::vector<float> values(2 * 3 * 4);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.5f * static_cast<float>(i);
  test::write_bytes(tmp / "a.npy", rec::encode_npy_f4({2, 3, 4}, values));
  rec::NpyFrameReader reader(tmp / "a.npy", rec::DType::f4);
  std::vector<float> frame(12);
  reader.read_frame(1, frame);
  CHECK(frame[11] == 11.5f);
  const std::string one_axis = rec::encode_npy_f4({5}, std::vector<float>(5, 1.0f));
  CHECK(one_axis.find("'shape': (5,)") != std::string::npos);
  CHECK(one_axis.size() % 64 == 20 % 64);  // 64-byte aligned header + 5 floats
  CHECK_THROWS_AS(rec::encode_npy_f4({2, 2}, std::vector<float>(3)), rec::Error);
}
