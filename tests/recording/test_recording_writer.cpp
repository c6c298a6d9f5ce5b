// RecordingWriter: temporary folder, commit by rename, nothing left behind on failure.

#include "rec_test_helpers.hpp"

using namespace bolo;
using bolo::test::contains;
using bolo::test::error_of;

namespace {

std::vector<std::uint16_t> flat(std::size_t n, std::uint16_t v) { return std::vector<std::uint16_t>(n, v); }

}  // namespace

TEST_CASE("writer: an abandoned writer leaves nothing behind", "[writer]") {
  test::TempDir tmp;
  {
    rec::RecordingWriter writer(tmp / "rec", test::fixture_info());
    writer.append(flat(15, 1), test::fixture_row(0));
    writer.add_file("poses.tum", "x");
    CHECK(test::folder_entries(tmp.path()).size() == 1);  // the hidden temporary folder
    CHECK(test::folder_entries(tmp.path())[0].starts_with(".rec.tmp-"));
  }
  CHECK(test::folder_entries(tmp.path()).empty());
}

TEST_CASE("writer: frames.csv is written as frames arrive, not held until commit", "[writer]") {
  // An endless `bolo run --sink recording:` must not grow with the frames it has written.
  test::TempDir tmp;
  rec::RecordingWriter writer(tmp / "rec", test::fixture_info());
  constexpr std::uint64_t kFrames = 5000;
  for (std::uint64_t i = 0; i < kFrames; ++i) writer.append(flat(15, 1), test::fixture_row(i));
  const auto entries = test::folder_entries(tmp.path());
  REQUIRE(entries.size() == 1);
  std::ifstream csv(tmp.path() / entries[0] / "frames.csv");
  std::string text((std::istreambuf_iterator<char>(csv)), std::istreambuf_iterator<char>());
  // Before commit, all but the rows still in the stream's buffer (a few kB) are in the file.
  CHECK(std::count(text.begin(), text.end(), '\n') > static_cast<std::ptrdiff_t>(kFrames * 9 / 10));
  writer.commit();
  CHECK(rec::Recording(tmp / "rec").frame_count() == kFrames);
}

TEST_CASE("writer: a failed run leaves nothing behind", "[writer][bad-input]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  {
    rec::RecordingWriter writer(dir, test::fixture_info());
    writer.append(flat(15, 1), test::fixture_row(0));
    // Frame size mismatch: the message names the destination, the frame and both sizes.
    CHECK(error_of([&] { writer.append(flat(14, 1), test::fixture_row(1)); }) ==
          (dir / "frames.npy").string() + ": frame 1: 14 pixels, expected 15 (3x5)");
    // A bad row is refused at append, naming frames.csv, the frame and the field.
    rec::FrameRow row = test::fixture_row(1);
    row.t_s = -1.0;
    CHECK(error_of([&] { writer.append(flat(15, 1), row); }) ==
          (dir / "frames.csv").string() + ": frame 1: field t_s: not monotonic (-1 after 0)");
    row = test::fixture_row(1);
    row.exposure_s = -0.5;
    CHECK(contains(error_of([&] { writer.append(flat(15, 1), row); }), "frame 1: field exposure_s: negative (-0.5)"));
    CHECK(contains(error_of([&] { writer.append(std::vector<float>(15), test::fixture_row(1)); }),
                   "DType::f4"));
    CHECK(writer.frames() == 1);
  }
  CHECK(test::folder_entries(tmp.path()).empty());
}

TEST_CASE("writer: an existing destination is refused before any work", "[writer][bad-input]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  test::make_fixture(dir, 2);
  const std::string before = test::read_bytes(dir / "frames.npy");
  CHECK(error_of([&] { rec::RecordingWriter w(dir, test::fixture_info()); }) ==
        dir.string() + ": already exists (use --overwrite to replace it)");
  // Also with a trailing slash.
  CHECK(contains(error_of([&] { rec::RecordingWriter w(dir.string() + "/", test::fixture_info()); }),
                 "already exists"));
  CHECK(test::folder_entries(tmp.path()) == std::vector<std::string>{"rec"});
  CHECK(test::read_bytes(dir / "frames.npy") == before);

  // A missing parent folder is an error too, and nothing is created.
  CHECK(contains(error_of([&] { rec::RecordingWriter w(tmp / "a" / "b", test::fixture_info()); }),
                 "parent folder"));
  CHECK(test::folder_entries(tmp.path()) == std::vector<std::string>{"rec"});
  // Invalid info is refused up front.
  rec::RecordingInfo info = test::fixture_info();
  info.width = 0;
  CHECK(contains(error_of([&] { rec::RecordingWriter w(tmp / "new", info); }), "field width"));
  CHECK(test::folder_entries(tmp.path()) == std::vector<std::string>{"rec"});
}

TEST_CASE("writer: overwrite replaces a recording, never anything else", "[writer]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  test::make_fixture(dir, 2);
  test::write_bytes(dir / "stale.txt", "from the old recording");
  rec::RecordingWriter::Options options;
  options.overwrite = true;
  {
    rec::RecordingWriter writer(dir, test::fixture_info(), options);
    for (int f = 0; f < 3; ++f) writer.append(flat(15, 9), test::fixture_row(f));
    CHECK(rec::Recording(dir).frame_count() == 2);  // the old one stays readable until commit
    writer.commit();
  }
  CHECK(rec::Recording(dir).frame_count() == 3);
  CHECK(!std::filesystem::exists(dir / "stale.txt"));
  CHECK(test::folder_entries(tmp.path()) == std::vector<std::string>{"rec"});

  // A folder that is not a recording (and not empty) is never replaced.
  const auto other = tmp / "home";
  std::filesystem::create_directory(other);
  test::write_bytes(other / "thesis.tex", "precious");
  CHECK(contains(error_of([&] { rec::RecordingWriter w(other, test::fixture_info(), options); }),
                 "home: exists and is not a recording folder"));
  CHECK(test::read_bytes(other / "thesis.tex") == "precious");
  // An empty folder may be replaced.
  const auto empty = tmp / "empty";
  std::filesystem::create_directory(empty);
  {
    rec::RecordingWriter writer(empty, test::fixture_info(), options);
    writer.commit();
  }
  CHECK(rec::Recording(empty).frame_count() == 0);
}

TEST_CASE("writer: a destination that appears during the run is not clobbered", "[writer][bad-input]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  {
    rec::RecordingWriter writer(dir, test::fixture_info());
    writer.append(flat(15, 1), test::fixture_row(0));
    std::filesystem::create_directory(dir);
    test::write_bytes(dir / "mine.txt", "someone else's");
    CHECK(contains(error_of([&] { writer.commit(); }), dir.string() + ": appeared while writing"));
  }
  CHECK(test::folder_entries(tmp.path()) == std::vector<std::string>{"rec"});
  CHECK(test::folder_entries(dir) == std::vector<std::string>{"mine.txt"});
}

TEST_CASE("writer: misuse is reported", "[writer][bad-input]") {
  test::TempDir tmp;
  const auto dir = tmp / "rec";
  rec::RecordingWriter writer(dir, test::fixture_info());
  CHECK(contains(error_of([&] { writer.add_file("/etc/passwd", "x"); }), "relative path"));
  CHECK(contains(error_of([&] { writer.add_file("../escape", "x"); }), "relative path"));
  CHECK(contains(error_of([&] { writer.add_file("truth/../../escape", "x"); }), "relative path"));
  CHECK(contains(error_of([&] { writer.add_file("frames.csv", "x"); }), "written by RecordingWriter"));
  writer.add_file("poses.tum", "x");
  CHECK(contains(error_of([&] { writer.add_file("./poses.tum", "y"); }), "added twice"));
  CHECK(contains(error_of([&] { writer.set_camera(nlohmann::json::array()); }), "camera.json: expected a JSON object"));
  writer.commit();
  CHECK(contains(error_of([&] { writer.commit(); }), "twice"));
  CHECK(contains(error_of([&] { writer.append(flat(15, 1), test::fixture_row(0)); }), "after commit"));
  CHECK(rec::Recording(dir).frame_count() == 0);
}

TEST_CASE("write_file_atomically replaces a file and leaves no temporary", "[writer]") {
  test::TempDir tmp;
  const auto file = tmp / "out.txt";
  rec::write_file_atomically(file, "one");
  rec::write_file_atomically(file, std::string("two\0three", 9));
  CHECK(test::read_bytes(file) == std::string("two\0three", 9));
  CHECK(test::folder_entries(tmp.path()) == std::vector<std::string>{"out.txt"});
  CHECK(contains(error_of([&] { rec::write_file_atomically(tmp / "no" / "such.txt", "x"); }),
                 "such.txt: cannot create"));
}

TEST_CASE("writer: scene.npy round-trips and must match the frame count", "[writer]") {
  test::TempDir tmp;
  {
    rec::RecordingWriter writer(tmp / "sim", test::fixture_info());
    for (std::uint64_t i = 0; i < 3; ++i) {
      writer.append(flat(15, static_cast<std::uint16_t>(i)), test::fixture_row(i));
      std::vector<float> scene(15, 0.5f + static_cast<float>(i));
      writer.append_scene(scene);
    }
    writer.commit();
  }
  rec::Recording recording(tmp / "sim");
  REQUIRE(recording.has_scene());
  std::vector<float> scene(15);
  recording.read_scene(2, scene);
  CHECK(scene[7] == 2.5f);

  {
    rec::RecordingWriter writer(tmp / "short", test::fixture_info());
    writer.append(flat(15, 1), test::fixture_row(0));
    writer.append(flat(15, 1), test::fixture_row(1));
    writer.append_scene(std::vector<float>(15, 1.0f));
    CHECK(contains(error_of([&] { writer.append_scene(std::vector<float>(3)); }),
                   "scene.npy: frame 1: 3 pixels, expected 15"));
    CHECK(contains(error_of([&] { writer.commit(); }), "scene.npy: 1 scene frames for 2 frames"));
  }
  CHECK(!std::filesystem::exists(tmp / "short"));
}
