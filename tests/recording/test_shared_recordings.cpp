// The real recordings in ../shared/data/real (the cases report SKIP when it is absent).

#include "rec_test_helpers.hpp"

using namespace bolo;

TEST_CASE("shared: lepton3-possum reads as 160 frames of 120x160 counts", "[shared]") {
  const auto dir = test::shared_recording("lepton3-possum");
  if (dir.empty()) return;
  rec::Recording r(dir);
  CHECK(r.frame_count() == 160);
  CHECK(r.width() == 160);
  CHECK(r.height() == 120);
  CHECK(r.info().bits == 14);
  CHECK(r.info().units == rec::Units::counts);
  CHECK(r.info().fps == 8.7);
  CHECK(r.info().sensor == "FLIR Lepton 3");
  CHECK(r.info().extra.empty());
  CHECK(!r.has_scene());
  CHECK(!r.camera());
  CHECK(r.rows()[1].t_s == 0.114);
  CHECK(r.rows()[0].fpa_temp_c == 9.600000381469727);
  CHECK(!r.rows()[0].housing_temp_c);
  CHECK(!r.rows()[0].exposure_s);
  std::vector<std::uint16_t> frame(160 * 120);
  r.read_frame(0, frame);
  CHECK(frame[0] == 2047);
  CHECK(frame[1] == 2043);
  r.read_frame(159, frame);
  CHECK(frame.back() == 2458);
  for (std::uint16_t v : frame) REQUIRE(v < (1u << 14));
  std::vector<std::uint16_t> row(160);
  r.read_row(1, 0, row);
  CHECK(row[0] == 2047);
}

TEST_CASE("shared: lepton35-trailcam-ffc has its shutter event at frame 309", "[shared]") {
  const auto dir = test::shared_recording("lepton35-trailcam-ffc");
  if (dir.empty()) return;
  rec::Recording r(dir);
  CHECK(r.frame_count() == 379);
  CHECK(r.width() == 160);
  CHECK(r.height() == 120);
  CHECK(r.info().units == rec::Units::centikelvin);
  std::vector<std::uint64_t> ffc;
  for (const rec::FrameRow& row : r.rows()) {
    REQUIRE(row.ffc.has_value());
    if (*row.ffc) ffc.push_back(row.index);
  }
  CHECK(ffc == std::vector<std::uint64_t>{309});
  // The shutter closed for ~1.8 s between frames 308 and 309.
  CHECK(*r.rows()[309].t_s - *r.rows()[308].t_s > 1.5);
  std::vector<std::uint16_t> frame(160 * 120);
  r.read_frame(378, frame);
  CHECK(frame.back() == 29289);  // 292.89 K
}

TEST_CASE("shared: flirone-lepton-telemetry carries FPA and housing temperatures", "[shared]") {
  const auto dir = test::shared_recording("flirone-lepton-telemetry");
  if (dir.empty()) return;
  rec::Recording r(dir);
  CHECK(r.frame_count() == 20);
  CHECK(r.width() == 80);
  CHECK(r.height() == 60);
  CHECK(r.rows()[0].fpa_temp_c == 46.85);
  CHECK(r.rows()[0].housing_temp_c == 46.94);
  CHECK(r.rows()[19].fpa_temp_c == 46.84);
  CHECK(r.rows()[19].housing_temp_c == 46.93);
  for (const rec::FrameRow& row : r.rows()) CHECK(row.ffc == false);
  // Frames 0/1 and 10/11 are duplicates (same core frame counter), as the notes say.
  std::vector<std::uint16_t> a(80 * 60), b(80 * 60);
  r.read_frame(10, a);
  r.read_frame(11, b);
  CHECK(a == b);
  r.read_frame(12, b);
  CHECK(a != b);
}

TEST_CASE("shared: flir-t1030-hand has empty exposure, readout and ffc cells", "[shared]") {
  const auto dir = test::shared_recording("flir-t1030-hand");
  if (dir.empty()) return;
  rec::Recording r(dir);
  CHECK(r.frame_count() == 8);
  CHECK(r.width() == 1024);
  CHECK(r.height() == 768);
  CHECK(r.info().bits == 16);
  for (const rec::FrameRow& row : r.rows()) {
    CHECK(row.t_s.has_value());
    CHECK(!row.exposure_s);
    CHECK(!row.readout_s);
    CHECK(!row.ffc);
    CHECK(!row.fpa_temp_c);
    CHECK(!row.housing_temp_c);
  }
  std::vector<std::uint16_t> frame(1024 * 768);
  r.read_frame(7, frame);
  CHECK(frame.back() == 14102);
}

TEST_CASE("shared: copying a recording through RecordingWriter preserves it", "[shared][writer]") {
  const auto dir = test::shared_recording("flirone-lepton-telemetry");
  if (dir.empty()) return;
  rec::Recording in(dir);
  test::TempDir tmp;
  {
    rec::RecordingWriter writer(tmp / "copy", in.info());
    std::vector<std::uint16_t> frame(std::size_t{in.width()} * in.height());
    for (std::uint64_t f = 0; f < in.frame_count(); ++f) {
      in.read_frame(f, frame);
      writer.append(frame, in.rows()[f]);
    }
    writer.commit();
  }
  rec::Recording out(tmp / "copy");
  CHECK(out.info().sensor == in.info().sensor);
  CHECK(out.info().source == in.info().source);
  CHECK(out.info().notes == in.info().notes);
  CHECK(out.info().fps == in.info().fps);
  REQUIRE(out.frame_count() == in.frame_count());
  for (std::uint64_t f = 0; f < in.frame_count(); ++f) {
    CHECK(out.rows()[f].t_s == in.rows()[f].t_s);
    CHECK(out.rows()[f].fpa_temp_c == in.rows()[f].fpa_temp_c);
    CHECK(out.rows()[f].housing_temp_c == in.rows()[f].housing_temp_c);
    CHECK(out.rows()[f].ffc == in.rows()[f].ffc);
  }
  // frames.npy data is byte-identical (only the header padding may differ).
  const std::string a = test::read_bytes(dir / "frames.npy");
  const std::string b = test::read_bytes(tmp / "copy" / "frames.npy");
  CHECK(a.substr(rec::read_npy_header(dir / "frames.npy").data_offset) ==
        b.substr(rec::read_npy_header(tmp / "copy" / "frames.npy").data_offset));
}
