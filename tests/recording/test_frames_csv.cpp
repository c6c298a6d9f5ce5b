// frames.csv reading, writing and validation.

#include <cmath>
#include <limits>

#include "rec_test_helpers.hpp"

using namespace bolo;
using bolo::test::contains;
using bolo::test::error_of;

namespace {

const std::string kHeader = "index,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c\n";

// A valid 4-row frames.csv with `line` (1-based data row n -> frame n-1) replaced.
std::filesystem::path csv_with(const test::TempDir& tmp, std::size_t frame, const std::string& row) {
  std::vector<std::string> rows = {"0,0.0,0.01,0.02,0,30.5,31", "1,0.1,0.01,0.02,0,30.5,31",
                                   "2,0.2,0.01,0.02,1,30.5,31", "3,0.3,0.01,0.02,0,30.5,31"};
  rows.at(frame) = row;
  std::string text = kHeader;
  for (const std::string& r : rows) text += r + "\n";
  const auto file = tmp / "frames.csv";
  test::write_bytes(file, text);
  return file;
}

std::string csv_error(const test::TempDir& tmp, std::size_t frame, const std::string& row) {
  const auto file = csv_with(tmp, frame, row);
  return error_of([&] { rec::read_frames_csv(file); });
}

}  // namespace

TEST_CASE("frames.csv: write then read gives back exactly the same rows", "[csv]") {
  test::TempDir tmp;
  std::vector<rec::FrameRow> rows(5);
  const double values[] = {0.1, 1.0 / 3.0, 1e-7, 123456.789012345, 0.30000000000000004};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i].index = i;
    rows[i].t_s = 1e6 * static_cast<double>(i) + values[i];
  }
  rows[0].exposure_s = 0.0123;
  rows[1].readout_s = 0.0;
  rows[2].ffc = true;
  rows[3].ffc = false;
  rows[3].fpa_temp_c = -40.125;
  rows[4].housing_temp_c = 1e300;
  rows[4].exposure_s = std::numeric_limits<double>::denorm_min();
  rows[2].t_s.reset();  // unknown times are allowed between known ones
  const auto file = tmp / "frames.csv";
  rec::write_frames_csv(file, rows);
  const std::string text = test::read_bytes(file);
  CHECK(text.starts_with(kHeader));
  CHECK(contains(text, "\n2,,,,1,,\n"));

  const std::vector<rec::FrameRow> back = rec::read_frames_csv(file);
  REQUIRE(back.size() == rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    INFO("row " << i);
    CHECK(back[i].index == rows[i].index);
    CHECK(back[i].t_s == rows[i].t_s);
    CHECK(back[i].exposure_s == rows[i].exposure_s);
    CHECK(back[i].readout_s == rows[i].readout_s);
    CHECK(back[i].ffc == rows[i].ffc);
    CHECK(back[i].fpa_temp_c == rows[i].fpa_temp_c);
    CHECK(back[i].housing_temp_c == rows[i].housing_temp_c);
  }
  // Row by row, the same bytes.
  const auto streamed = tmp / "streamed.csv";
  {
    rec::FramesCsvWriter writer(streamed);
    for (const rec::FrameRow& row : rows) writer.append(row);
    CHECK(writer.rows() == rows.size());
    writer.finish();
  }
  CHECK(test::read_bytes(streamed) == text);
  // Header only: zero frames.
  rec::write_frames_csv(file, {});
  CHECK(rec::read_frames_csv(file).empty());
}

TEST_CASE("frames.csv: the row-by-row writer refuses a bad row before writing it", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  rec::FramesCsvWriter writer(file, tmp / "shown.csv");
  rec::FrameRow row;
  row.t_s = 1.0;
  writer.append(row);
  row.index = 1;
  row.t_s = 0.5;  // going back in time
  CHECK(error_of([&] { writer.append(row); }) == (tmp / "shown.csv").string() + ": frame 1: field t_s: not monotonic (0.5 after 1)");
  row.t_s.reset();  // unknown, then later than the last known one
  writer.append(row);
  row.index = 2;
  row.t_s = 0.75;
  CHECK(contains(error_of([&] { writer.append(row); }), "frame 2: field t_s: not monotonic"));
  row.t_s = 2.0;
  writer.append(row);
  writer.finish();
  CHECK(rec::read_frames_csv(file).size() == 3);
  CHECK(contains(error_of([&] { writer.append(row); }), "append after finish()"));
}

TEST_CASE("frames.csv: CRLF line ends, a BOM, spaces and trailing blank lines are accepted", "[csv]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  test::write_bytes(file,
                    "\xEF\xBB\xBFindex,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c\r\n"
                    "0,0.000000,,,0,9.600000381469727,\r\n"
                    "1, 0.114 ,1e-3,,1,,\r\n"
                    "\r\n\r\n");
  const auto rows = rec::read_frames_csv(file);
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].t_s == 0.0);
  CHECK(rows[0].fpa_temp_c == 9.600000381469727);
  CHECK(!rows[0].housing_temp_c);
  CHECK(rows[1].t_s == 0.114);
  CHECK(rows[1].exposure_s == 0.001);
  CHECK(rows[1].ffc == true);
}

TEST_CASE("frames.csv: a wrong header or column count is refused", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  test::write_bytes(file, "index,t_s,exposure_s,readout_s,ffc,fpa_temp_c\n0,0,,,,\n");
  std::string msg = error_of([&] { rec::read_frames_csv(file); });
  CHECK(contains(msg, file.string() + ": header: expected 'index,t_s,"));
  CHECK(contains(msg, "(6 columns)"));

  test::write_bytes(file, "index,exposure_s,t_s,readout_s,ffc,fpa_temp_c,housing_temp_c\n");
  CHECK(contains(error_of([&] { rec::read_frames_csv(file); }), ": header: expected"));

  test::write_bytes(file, "");
  CHECK(contains(error_of([&] { rec::read_frames_csv(file); }), file.string() + ": empty file"));

  // A data row with a missing column.
  msg = csv_error(tmp, 2, "2,0.2,0.01,0.02,1,30.5");
  CHECK(msg == file.string() + ": frame 2: 6 columns, expected 7 "
                               "(index,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c)");
  CHECK(contains(csv_error(tmp, 1, "1,0.1,0.01,0.02,0,30.5,31,9"), "frame 1: 8 columns, expected 7"));
  CHECK(contains(csv_error(tmp, 1, ""), "frame 1: empty line"));
}

TEST_CASE("frames.csv: index must equal the row number", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  CHECK(csv_error(tmp, 2, "3,0.2,0.01,0.02,1,30.5,31") ==
        file.string() + ": frame 2: field index: 3, expected 2 (index must equal the row number)");
  CHECK(contains(csv_error(tmp, 2, ",0.2,0.01,0.02,1,30.5,31"), "frame 2: field index: empty"));
  CHECK(contains(csv_error(tmp, 2, "2.0,0.2,0.01,0.02,1,30.5,31"), "frame 2: field index: not a non-negative integer: '2.0'"));
}

TEST_CASE("frames.csv: t_s must increase strictly", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  test::write_bytes(file, kHeader + "0,0.5,,,,,\n1,1.0,,,,,\n2,0.9,,,,,\n");
  CHECK(error_of([&] { rec::read_frames_csv(file); }) ==
        file.string() + ": frame 2: field t_s: not monotonic (0.9 after 1.0)");
  // Equal times are not increasing either; unknown times in between do not reset the check.
  test::write_bytes(file, kHeader + "0,0.5,,,,,\n1,,,,,,\n2,0.5,,,,,\n");
  CHECK(error_of([&] { rec::read_frames_csv(file); }) ==
        file.string() + ": frame 2: field t_s: not monotonic (0.5 after 0.5)");
}

TEST_CASE("frames.csv: NaN and Inf in any numeric field name the frame and the field", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  CHECK(csv_error(tmp, 1, "1,nan,0.01,0.02,0,30.5,31") ==
        file.string() + ": frame 1: field t_s: not finite (nan)");
  CHECK(csv_error(tmp, 3, "3,0.3,inf,0.02,0,30.5,31") ==
        file.string() + ": frame 3: field exposure_s: not finite (inf)");
  CHECK(csv_error(tmp, 2, "2,0.2,0.01,-inf,1,30.5,31") ==
        file.string() + ": frame 2: field readout_s: not finite (-inf)");
  CHECK(csv_error(tmp, 0, "0,0.0,0.01,0.02,0,NaN,31") ==
        file.string() + ": frame 0: field fpa_temp_c: not finite (nan)");
  CHECK(csv_error(tmp, 0, "0,0.0,0.01,0.02,0,30,Infinity") ==
        file.string() + ": frame 0: field housing_temp_c: not finite (inf)");
  CHECK(contains(csv_error(tmp, 0, "0,0.0,0.01,0.02,0,1e999,31"),
                 "frame 0: field fpa_temp_c: out of range: '1e999'"));
}

TEST_CASE("frames.csv: garbage in a number is refused (locale-independent parsing)", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  CHECK(csv_error(tmp, 1, "1,0.1abc,0.01,0.02,0,30.5,31") ==
        file.string() + ": frame 1: field t_s: not a number: '0.1abc'");
  CHECK(csv_error(tmp, 1, "1,0.1,0.01,0.02,0,\"30,5\",31").find("frame 1") != std::string::npos);
  CHECK(contains(csv_error(tmp, 1, "1,0.1,0.01,0.02,0,30.5.1,31"), "field fpa_temp_c: not a number: '30.5.1'"));
  CHECK(contains(csv_error(tmp, 1, "1,0.1,0x10,0.02,0,30.5,31"), "field exposure_s: not a number: '0x10'"));
}

TEST_CASE("frames.csv: negative exposure or readout is refused", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  CHECK(csv_error(tmp, 2, "2,0.2,-0.001,0.02,1,30.5,31") ==
        file.string() + ": frame 2: field exposure_s: negative (-0.001)");
  CHECK(csv_error(tmp, 3, "3,0.3,0.01,-1,0,30.5,31") ==
        file.string() + ": frame 3: field readout_s: negative (-1)");
}

TEST_CASE("frames.csv: ffc must be 0, 1 or empty", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  CHECK(csv_error(tmp, 1, "1,0.1,0.01,0.02,2,30.5,31") ==
        file.string() + ": frame 1: field ffc: '2', expected 0, 1 or empty");
  CHECK(contains(csv_error(tmp, 1, "1,0.1,0.01,0.02,true,30.5,31"), "frame 1: field ffc: 'true'"));
  CHECK(contains(csv_error(tmp, 1, "1,0.1,0.01,0.02,1.0,30.5,31"), "frame 1: field ffc: '1.0'"));
}

TEST_CASE("frames.csv: writing invalid rows is refused before anything is written", "[csv][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "frames.csv";
  std::vector<rec::FrameRow> rows(2);
  rows[0].index = 0;
  rows[1].index = 1;
  rows[1].exposure_s = std::nan("");
  CHECK(error_of([&] { rec::write_frames_csv(file, rows); }) ==
        file.string() + ": frame 1: field exposure_s: not finite (nan)");
  rows[1].exposure_s.reset();
  rows[1].index = 5;
  CHECK(contains(error_of([&] { rec::write_frames_csv(file, rows); }), "frame 1: field index: 5, expected 1"));
  rows[1].index = 1;
  rows[0].t_s = 2.0;
  rows[1].t_s = 1.5;
  CHECK(error_of([&] { rec::write_frames_csv(file, rows); }) ==
        file.string() + ": frame 1: field t_s: not monotonic (1.5 after 2)");
  CHECK(!std::filesystem::exists(file));
  CHECK(test::folder_entries(tmp.path()).empty());
}
