// Recording: a folder read as a whole, validated on open.

#include "rec_test_helpers.hpp"

using namespace bolo;
using bolo::test::contains;
using bolo::test::error_of;

TEST_CASE("recording: writer -> reader round trip (uint16, camera, extras, scene)", "[recording]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  rec::RecordingInfo info = test::fixture_info(3, 5);
  info.units = rec::Units::counts8;
  info.notes = "round trip";
  info.extra["simulator"] = {{"tau_h", 0.012}, {"seed", 7}};
  std::string scene_data;
  {
    rec::RecordingWriter writer(dir, info);
    std::vector<std::uint16_t> frame(15);
    std::vector<float> scene;
    for (std::uint64_t f = 0; f < 4; ++f) {
      for (std::size_t p = 0; p < frame.size(); ++p) {
        frame[p] = test::fixture_value(f, p);
        scene.push_back(0.5f + static_cast<float>(frame[p]));
      }
      rec::FrameRow row = test::fixture_row(f);
      row.index = 99;  // ignored: the writer numbers rows itself
      if (f == 3) row.fpa_temp_c.reset();
      writer.append(frame, row);
    }
    CHECK(writer.frames() == 4);
    writer.set_camera({{"model", "pinhole"}, {"fx", 100.5}, {"fy", 100.5}, {"cx", 2}, {"cy", 1}});
    writer.add_file("poses.tum", "0 0 0 0 0 0 0 1\n");
    writer.add_file("truth/ghost.txt", "secret\n");
    scene_data = test::npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (4, 3, 5), }",
                                 test::le_f32(scene));
    writer.add_file("scene.npy", scene_data);
    CHECK(!std::filesystem::exists(dir));  // nothing visible before commit
    writer.commit();
  }
  CHECK(test::folder_entries(tmp.path()) == std::vector<std::string>{"rec"});
  CHECK(test::folder_entries(dir) ==
        std::vector<std::string>{"camera.json", "frames.csv", "frames.npy", "poses.tum",
                                 "recording.json", "scene.npy", "truth"});
  CHECK(test::read_bytes(dir / "truth" / "ghost.txt") == "secret\n");

  rec::Recording recording(dir);
  CHECK(recording.dir() == dir);
  CHECK(recording.frame_count() == 4);
  CHECK(recording.width() == 5);
  CHECK(recording.height() == 3);
  CHECK(recording.info().units == rec::Units::counts8);
  CHECK(recording.info().notes == "round trip");
  CHECK(recording.info().fps == 10.0);
  CHECK(recording.info().bits == 14);
  CHECK(recording.info().extra == info.extra);
  REQUIRE(recording.camera());
  CHECK((*recording.camera())["fx"] == 100.5);
  for (std::uint64_t f = 0; f < 4; ++f) {
    const rec::FrameRow& row = recording.rows()[f];
    rec::FrameRow expected = test::fixture_row(f);
    CHECK(row.index == f);
    CHECK(row.t_s == expected.t_s);
    CHECK(row.exposure_s == expected.exposure_s);
    CHECK(row.readout_s == expected.readout_s);
    CHECK(row.ffc == expected.ffc);
    CHECK(row.fpa_temp_c == (f == 3 ? std::nullopt : expected.fpa_temp_c));
    CHECK(row.housing_temp_c == expected.housing_temp_c);
  }
  std::vector<std::uint16_t> frame(15);
  recording.read_frame(2, frame);
  for (std::size_t p = 0; p < 15; ++p) CHECK(frame[p] == test::fixture_value(2, p));
  std::vector<std::uint16_t> row(5);
  recording.read_row(3, 1, row);
  CHECK(row[0] == test::fixture_value(3, 5));
  REQUIRE(recording.has_scene());
  std::vector<float> scene(15);
  recording.read_scene(3, scene);
  CHECK(scene[14] == 0.5f + static_cast<float>(test::fixture_value(3, 14)));
}

TEST_CASE("recording: float32 output (frames_dtype f4) writes a '<f4' frames.npy", "[recording]") {
  test::TempDir tmp;
  const auto dir = tmp / "corrected";
  rec::RecordingWriter::Options options;
  options.frames_dtype = rec::DType::f4;
  {
    rec::RecordingWriter writer(dir, test::fixture_info(2, 2), options);
    writer.append(std::vector<float>{0.25f, -1.5f, 3e4f, 7.0f}, test::fixture_row(0));
    writer.append(std::vector<std::uint16_t>{1, 2, 3, 65535}, test::fixture_row(1));
    writer.commit();
  }
  const rec::NpyHeader header = rec::read_npy_header(dir / "frames.npy");
  CHECK(header.dtype == rec::DType::f4);
  CHECK(header.shape == std::vector<std::uint64_t>{2, 2, 2});
  rec::NpyFrameReader reader(dir / "frames.npy", rec::DType::f4);
  std::vector<float> frame(4);
  reader.read_frame(0, frame);
  CHECK(frame == std::vector<float>{0.25f, -1.5f, 3e4f, 7.0f});
  reader.read_frame(1, frame);
  CHECK(frame == std::vector<float>{1, 2, 3, 65535});
  CHECK(rec::read_frames_csv(dir / "frames.csv").size() == 2);
  CHECK(rec::read_recording_json(dir / "recording.json").width == 2);
  // The format's frames.npy is uint16, so Recording refuses it with the dtype named.
  CHECK(error_of([&] { rec::Recording r(dir); }) ==
        (dir / "frames.npy").string() + ": dtype '<f4', expected '<u2'");
}

TEST_CASE("recording: frames.npy shape disagreeing with recording.json is refused", "[recording][bad-input]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  test::make_fixture(dir);
  test::write_bytes(dir / "frames.npy",
                    test::npy_bytes("{'descr': '<u2', 'fortran_order': False, 'shape': (4, 5, 3), }",
                                    std::string(4 * 15 * 2, '\0')));
  CHECK(error_of([&] { rec::Recording r(dir); }) ==
        (dir / "frames.npy").string() + ": shape (4, 5, 3) disagrees with recording.json (3x5)");
}

TEST_CASE("recording: frames.csv row count must equal frames.npy N", "[recording][bad-input]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  test::make_fixture(dir, 4);
  std::string csv = test::read_bytes(dir / "frames.csv");
  csv.erase(csv.rfind('\n', csv.size() - 2) + 1);  // drop the last row
  test::write_bytes(dir / "frames.csv", csv);
  CHECK(error_of([&] { rec::Recording r(dir); }) ==
        (dir / "frames.csv").string() + ": 3 rows but frames.npy has 4 frames");
}

TEST_CASE("recording: errors inside the folder's files name the file", "[recording][bad-input]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  test::make_fixture(dir, 4);
  const std::string csv = test::read_bytes(dir / "frames.csv");
  const std::string npy = test::read_bytes(dir / "frames.npy");

  SECTION("truncated frames.npy") {
    std::filesystem::resize_file(dir / "frames.npy", npy.size() - 1);
    CHECK(error_of([&] { rec::Recording r(dir); }) ==
          (dir / "frames.npy").string() +
              ": truncated: header declares 4 frames of 3x5 uint16 (120 bytes) but the file has 119 "
              "bytes of data");
  }
  SECTION("frames.npy that is not .npy") {
    test::write_bytes(dir / "frames.npy", "PNG?");
    CHECK(error_of([&] { rec::Recording r(dir); }) == (dir / "frames.npy").string() + ": not a .npy file (bad magic)");
  }
  SECTION("missing frames.csv") {
    std::filesystem::remove(dir / "frames.csv");
    CHECK(contains(error_of([&] { rec::Recording r(dir); }), (dir / "frames.csv").string() + ": cannot open"));
  }
  SECTION("bad row in frames.csv") {
    test::replace_line(dir / "frames.csv", 3, "2,0.2,0.01,0.02,7,30.5,31.25");
    CHECK(error_of([&] { rec::Recording r(dir); }) ==
          (dir / "frames.csv").string() + ": frame 2: field ffc: '7', expected 0, 1 or empty");
  }
  SECTION("missing recording.json") {
    std::filesystem::remove(dir / "recording.json");
    CHECK(contains(error_of([&] { rec::Recording r(dir); }), "no recording.json"));
  }
  SECTION("no such folder") {
    CHECK(error_of([&] { rec::Recording r(tmp / "absent"); }) ==
          (tmp / "absent").string() + ": no such recording folder");
  }
  SECTION("scene.npy of the wrong dtype or shape") {
    test::write_bytes(dir / "scene.npy", npy);  // a uint16 copy
    CHECK(error_of([&] { rec::Recording r(dir); }) == (dir / "scene.npy").string() + ": dtype '<u2', expected '<f4'");
    test::write_bytes(dir / "scene.npy",
                      test::npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (3, 3, 5), }",
                                      std::string(3 * 15 * 4, '\0')));
    CHECK(error_of([&] { rec::Recording r(dir); }) ==
          (dir / "scene.npy").string() + ": shape (3, 3, 5) disagrees with frames.npy (4, 3, 5)");
  }
  SECTION("camera.json not an object") {
    test::write_bytes(dir / "camera.json", "[1, 2]");
    CHECK(error_of([&] { rec::Recording r(dir); }) == (dir / "camera.json").string() + ": expected a JSON object");
    test::write_bytes(dir / "camera.json", "{\"fx\": NaN}");
    CHECK(contains(error_of([&] { rec::Recording r(dir); }), "camera.json: field fx: NaN"));
  }
  SECTION("no scene: read_scene is an error") {
    rec::Recording r(dir);
    CHECK(!r.has_scene());
    std::vector<float> out(15);
    CHECK(contains(error_of([&] { r.read_scene(0, out); }), "scene.npy: absent"));
  }
}
