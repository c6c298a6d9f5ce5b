// The refusals of docs/errors.md that test_refusals.cpp and tests/recording do not already
// trigger through the command line: each one exits 2 with one `bolo: error:` line naming the
// file, frame, field or flag, and leaves nothing behind (the test folder holds exactly what it
// held before).

#include <catch2/catch.hpp>

#include "../recording/rec_test_helpers.hpp"
#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

// Replaces one cell of frames.csv (frame = data row, column by name).
void set_cell(const fs::path& csv, std::uint64_t frame, const std::string& column, const std::string& value) {
  static const std::vector<std::string> kColumns = {"index", "t_s", "exposure_s", "readout_s",
                                                    "ffc", "fpa_temp_c", "housing_temp_c"};
  const auto col = static_cast<std::size_t>(
      std::find(kColumns.begin(), kColumns.end(), column) - kColumns.begin());
  REQUIRE(col < kColumns.size());
  std::istringstream in(read_text(csv));
  std::string text, line;
  for (std::uint64_t n = 0; std::getline(in, line); ++n) {
    if (n == frame + 1) {
      std::vector<std::string> cells;
      std::string cell;
      std::istringstream cs(line);
      while (std::getline(cs, cell, ',')) cells.push_back(cell);
      cells.resize(kColumns.size());
      cells[col] = value;
      line.clear();
      for (std::size_t c = 0; c < cells.size(); ++c) line += (c ? "," : "") + cells[c];
    }
    text += line + "\n";
  }
  write_bytes(csv, text);
}

// A recording of the small recording's size with `frames` frames (0 allowed).
void write_frames(const fs::path& dir, std::uint64_t frames) {
  rec::RecordingInfo info;
  info.width = SmallRecording::kWidth;
  info.height = SmallRecording::kHeight;
  info.bits = 14;
  rec::RecordingWriter writer(dir, info);
  for (std::uint64_t i = 0; i < frames; ++i) writer.append(SmallRecording::frame(i), SmallRecording::row(i));
  writer.commit();
}

}  // namespace

// ---- bolo correct: flags ---------------------------------------------------------------------

TEST_CASE("catalogue: correct --exposure/--readout must be times > 0", "[cli][refusal][catalogue]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::set<std::string> before = entries(tmp.path());
  CHECK(contains(refused(with(correct_args(tmp), {"--exposure=-1"})), "--exposure -1: must be a finite time in seconds, > 0"));
  CHECK(contains(refused(with(correct_args(tmp), {"--readout", "0"})), "--readout 0: must be a finite time in seconds, > 0"));
  CHECK(contains(refused(with(correct_args(tmp), {"--readout", "5"})), "--readout 5: too long (the firmware takes at most 4.29 s)"));
  CHECK(entries(tmp.path()) == before);
}

TEST_CASE("catalogue: correct times below the firmware's 1 ns resolution", "[cli][refusal][catalogue]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::set<std::string> before = entries(tmp.path());
  CHECK(contains(refused({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "0.012", "--tau-c", "1e-10"}),
            "--tau-c 1e-10: below the firmware's 1 ns resolution"));
  CHECK(contains(refused(with(correct_args(tmp), {"--exposure", "4e-10"})), "--exposure 4e-10: below the firmware's 1 ns resolution"));
  CHECK(entries(tmp.path()) == before);
}

TEST_CASE("catalogue: correct --nominal-fps outside 0.25 .. 1e6", "[cli][refusal][catalogue]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::set<std::string> before = entries(tmp.path());
  CHECK(contains(refused(with(correct_args(tmp), {"--nominal-fps", "0.1"})),
            "--nominal-fps 0.1: must be a frame rate between 0.25 and 1e6"));
  CHECK(contains(refused(with(correct_args(tmp), {"--nominal-fps", "2e6"})), "--nominal-fps 2000000: must be a frame rate"));
  CHECK(entries(tmp.path()) == before);
}

// ---- bolo correct: OUT and --stats -------------------------------------------------------------

TEST_CASE("catalogue: correct OUT empty or in a missing folder", "[cli][refusal][catalogue]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::set<std::string> before = entries(tmp.path());
  CHECK(contains(refused({"correct", (tmp / "rec").string(), "", "--tau-h", "0.012", "--tau-c", "0.012"}), "OUT: empty path"));
  const fs::path out = tmp / "no" / "out";
  CHECK(contains(refused({"correct", (tmp / "rec").string(), out.string(), "--tau-h", "0.012", "--tau-c", "0.012"}),
            out.string() + ": parent folder " + (tmp / "no").string() + " does not exist"));
  CHECK(entries(tmp.path()) == before);
}

TEST_CASE("catalogue: correct --stats that is a folder, or exists without --overwrite", "[cli][refusal][catalogue]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  fs::create_directory(tmp / "stats-dir");
  std::ofstream(tmp / "old.csv") << "keep";
  const std::set<std::string> before = entries(tmp.path());
  const fs::path dir = tmp / "stats-dir";
  CHECK(contains(refused(with(correct_args(tmp), {"--stats", dir.string()})), "--stats " + dir.string() + ": is a folder"));
  const fs::path old = tmp / "old.csv";
  CHECK(contains(refused(with(correct_args(tmp), {"--stats", old.string()})),
            "--stats " + old.string() + ": already exists (use --overwrite to replace it)"));
  CHECK(read_text(old) == "keep");
  CHECK(entries(tmp.path()) == before);
}

// ---- every command: the recording folder -------------------------------------------------------

TEST_CASE("catalogue: REC that is a file, not a folder", "[cli][refusal][catalogue]") {
  TempDir tmp;
  std::ofstream(tmp / "rec.npy") << "not a folder";
  const std::string file = (tmp / "rec.npy").string();
  const std::string expected = file + ": not a folder (a recording is a folder with recording.json, frames.npy, frames.csv)";
  CHECK(contains(refused({"info", file}), expected));
  CHECK(contains(refused(with(correct_args(tmp, "rec.npy"), {"--exposure", "0.01", "--readout", "0.01"})), expected));
  CHECK(contains(refused({"render", file, (tmp / "x.png").string()}), expected));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec.npy"});
}

TEST_CASE("catalogue: a recording folder without frames.npy, recording.json or frames.csv", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const fs::path rec = tmp / "rec";
  const std::string png = (tmp / "x.png").string();
  SECTION("frames.npy missing") {
    SmallRecording::write(rec);
    fs::remove(rec / "frames.npy");
    const std::string npy = (rec / "frames.npy").string();
    CHECK(contains(refused({"info", rec.string()}), npy + ": missing (every recording has frames.npy)"));
    CHECK(contains(refused({"render", rec.string(), png}), npy + ": missing (every recording has frames.npy)"));
    CHECK(contains(refused(correct_args(tmp)), npy + ": cannot open: No such file or directory"));
  }
  SECTION("recording.json missing") {
    SmallRecording::write(rec);
    fs::remove(rec / "recording.json");
    for (const auto& args : {std::vector<std::string>{"info", rec.string()},
                             std::vector<std::string>{"render", rec.string(), png}, correct_args(tmp)})
      CHECK(contains(refused(args), rec.string() + ": not a recording folder (no recording.json)"));
  }
  SECTION("frames.csv missing") {
    SmallRecording::write(rec);
    fs::remove(rec / "frames.csv");
    for (const auto& args : {std::vector<std::string>{"info", rec.string()},
                             std::vector<std::string>{"render", rec.string(), png}, correct_args(tmp)})
      CHECK(contains(refused(args), (rec / "frames.csv").string() + ": cannot open: No such file or directory"));
  }
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec"});
}

TEST_CASE("catalogue: a recording without frames cannot be corrected or rendered", "[cli][refusal][catalogue]") {
  TempDir tmp;
  write_frames(tmp / "rec", 0);
  const std::set<std::string> before = entries(tmp.path());
  CHECK(contains(refused(correct_args(tmp)), (tmp / "rec" / "frames.csv").string() + ": no frames"));
  CHECK(contains(refused({"render", (tmp / "rec").string(), (tmp / "x.png").string()}), (tmp / "rec").string() + ": no frames"));
  CHECK(run_bolo({"info", (tmp / "rec").string()}).code == 0);  // describing it is fine
  CHECK(entries(tmp.path()) == before);
}

// ---- recording.json, frames.csv, frames.npy through the command line ----------------------------

TEST_CASE("catalogue: bad recording.json names the file and the field", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const fs::path rec = tmp / "rec";
  SmallRecording::write(rec);
  const fs::path json = rec / "recording.json";
  const std::string good = read_text(json);
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
    write_bytes(json, text);
  };
  replaced("\"width\": 24", "\"width\": 0");
  CHECK(contains(refused({"info", rec.string()}), json.string() + ": field width: 0, expected an integer from 1 to"));
  replaced("\"fps\": 10.0", "\"fps\": NaN");
  CHECK(contains(refused(correct_args(tmp)), json.string() + ": field fps: NaN is not a finite number"));
  replaced("\"units\": \"counts\"", "\"units\": \"kelvin\"");
  CHECK(contains(refused({"render", rec.string(), (tmp / "x.png").string()}),
            json.string() + ": field units: 'kelvin', expected counts, centikelvin or counts8"));
  replaced("\"units\": \"counts\"", "\"units\": 3");
  CHECK(contains(refused({"info", rec.string()}), json.string() + ": field units: 3, expected a string"));
  write_bytes(json, "{\"format\": \"bolo-recording\",");
  CHECK(contains(refused({"info", rec.string()}), json.string() + ": invalid JSON: "));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec"});
}

TEST_CASE("catalogue: bad frames.csv names the file, the frame and the field", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const fs::path rec = tmp / "rec";
  SmallRecording::write(rec);
  const fs::path csv = rec / "frames.csv";
  const std::string good = read_text(csv);
  set_cell(csv, 5, "t_s", "0.1");  // before frame 4's time
  CHECK(contains(refused(correct_args(tmp)), csv.string() + ": frame 5: field t_s: not monotonic (0.1 after "));
  write_bytes(csv, good);
  set_cell(csv, 2, "ffc", "yes");
  CHECK(contains(refused({"info", rec.string()}), csv.string() + ": frame 2: field ffc: 'yes', expected 0, 1 or empty"));
  write_bytes(csv, good);
  set_cell(csv, 8, "readout_s", "-0.004");
  CHECK(contains(refused({"render", rec.string(), (tmp / "x.png").string()}), csv.string() + ": frame 8: field readout_s: negative (-0.004)"));
  write_bytes(csv, "index,t_s\n0,0\n");
  CHECK(contains(refused({"info", rec.string()}), csv.string() + ": header: expected 'index,t_s,exposure_s,"));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec"});
}

TEST_CASE("catalogue: frames.csv timing the firmware cannot take", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const fs::path rec = tmp / "rec";
  SmallRecording::write(rec);
  const fs::path csv = rec / "frames.csv";
  const std::string good = read_text(csv);
  set_cell(csv, 4, "exposure_s", "5");
  CHECK(contains(refused(correct_args(tmp)), csv.string() + ": frame 4: field exposure_s: out of range for the firmware (0 to 4.29 s)"));
  write_bytes(csv, good);
  set_cell(csv, 11, "t_s", "1e10");
  CHECK(contains(refused(correct_args(tmp)), csv.string() + ": frame 11: field t_s: out of range"));
  write_bytes(csv, good);
  set_cell(csv, 3, "exposure_s", "0");
  CHECK(contains(refused(correct_args(tmp)),
            csv.string() + ": frame 3: field exposure_s: 0 s is zero for the firmware (unknown) and no --exposure given"));
  set_cell(csv, 3, "exposure_s", "1e-10");  // rounds to 0 ns
  CHECK(contains(refused(correct_args(tmp)), "frame 3: field exposure_s: 1e-10 s is zero for the firmware"));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec"});
}

TEST_CASE("catalogue: frames.npy that disagrees with its recording", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const fs::path rec = tmp / "rec";
  SmallRecording::write(rec);
  const fs::path npy = rec / "frames.npy";
  const std::string png = (tmp / "x.png").string();
  const std::string pixels(std::size_t{12} * 16 * 24 * 2, '\0');
  write_bytes(npy, "GIF89a");
  CHECK(contains(refused({"info", rec.string()}), npy.string() + ": not a .npy file (bad magic)"));
  write_bytes(npy, npy_bytes("{'descr': '>u2', 'fortran_order': False, 'shape': (12, 16, 24), }", pixels));
  CHECK(contains(refused(correct_args(tmp)), npy.string() + ": dtype '>u2', expected '<u2'"));
  CHECK(contains(refused({"render", rec.string(), png}), npy.string() + ": dtype '>u2' not supported (expected '<u2' or '<f4')"));
  write_bytes(npy, npy_bytes("{'descr': '<u2', 'fortran_order': False, 'shape': (12, 24, 16), }", pixels));
  CHECK(contains(refused({"info", rec.string()}), npy.string() + ": shape (12, 24, 16) disagrees with recording.json (16x24)"));
  write_bytes(npy, npy_bytes("{'descr': '<u2', 'fortran_order': False, 'shape': (11, 16, 24), }", pixels));
  CHECK(contains(refused(correct_args(tmp)), (rec / "frames.csv").string() + ": 12 rows but frames.npy has 11 frames"));
  write_bytes(npy, std::string("\x93NUMPY\x01", 7));
  CHECK(contains(refused({"info", rec.string()}), npy.string() + ": truncated: the file ends inside the .npy preamble"));
  write_bytes(npy, npy_bytes("{'descr': '<u2', 'fortran_order': False, 'shape': (1099511627776, 1099511627776, 24), }", pixels));
  CHECK(contains(refused({"render", rec.string(), png}),
            npy.string() + ": shape (1099511627776, 1099511627776, 24) is too large"));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec"});
}

TEST_CASE("catalogue: float32 frames.npy (correct --float output) that disagrees", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const fs::path rec = tmp / "rec";
  SmallRecording::write(rec);
  const fs::path npy = rec / "frames.npy";
  const std::string png = (tmp / "x.png").string();
  write_bytes(npy, npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (12, 384), }", std::string(12 * 384 * 4, '\0')));
  // (FrameStack's own "expected shape (N, H, W)" check never fires: the reader refuses first.)
  CHECK(contains(refused({"info", rec.string()}), npy.string() + ": shape (12, 384) is not a stack of frames (N, H, W)"));
  const std::string pixels(std::size_t{12} * 16 * 24 * 4, '\0');
  write_bytes(npy, npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (12, 24, 16), }", pixels));
  CHECK(contains(refused({"render", rec.string(), png}), npy.string() + ": frames are 16x24 but recording.json says 24x16"));
  write_bytes(npy, npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (10, 16, 24), }", pixels));
  CHECK(contains(refused({"info", rec.string()}), npy.string() + ": 10 frames but frames.csv has 12 rows"));
  // correct reads uint16 only: its input is raw counts.
  write_bytes(npy, npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (12, 16, 24), }", pixels));
  CHECK(contains(refused(correct_args(tmp)), npy.string() + ": dtype '<f4', expected '<u2'"));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec"});
}

TEST_CASE("catalogue: scene.npy and camera.json that do not fit", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const fs::path rec = tmp / "rec";
  SmallRecording::write(rec);
  write_bytes(rec / "scene.npy", npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (3, 16, 24), }",
                                           std::string(std::size_t{3} * 16 * 24 * 4, '\0')));
  CHECK(contains(refused(correct_args(tmp)), (rec / "scene.npy").string() + ": shape (3, 16, 24) disagrees with frames.npy (12, 16, 24)"));
  fs::remove(rec / "scene.npy");
  write_bytes(rec / "camera.json", "[1, 2]");
  CHECK(contains(refused(correct_args(tmp)), (rec / "camera.json").string() + ": expected a JSON object"));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec"});
}

// ---- bolo render ---------------------------------------------------------------------------------

TEST_CASE("catalogue: render flag combinations and limits", "[cli][refusal][catalogue]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::string rec = (tmp / "rec").string(), png = (tmp / "x.png").string();
  const std::set<std::string> before = entries(tmp.path());
  const std::string both = refused({"render", rec, png, "--range", "0:1", "--percentile", "1:99"});
  CHECK(contains(both, "--range"));
  CHECK(contains(both, "--percentile"));
  CHECK(contains(refused({"render", rec, png, "--range", "0:1", "--agc"}), "--range and --agc: choose one (--agc picks a range per frame)"));
  // (the limits are checked by run_render, or by CLI11 first where the option has a range check)
  for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
           {"--count", "0"}, {"--count", "5000"}, {"--columns", "0"}, {"--columns", "300"}, {"--scale", "0"}, {"--scale", "65"}}) {
    const std::string err = refused({"render", rec, png, "--contact-sheet", flag, value});
    CHECK(contains(err, flag));
    CHECK(contains(err, value));
  }
  CHECK(contains(refused({"render", rec, png, "--percentile", "x"}), "--percentile x: expected P_LO:P_HI (two numbers separated by ':')"));
  CHECK(contains(refused({"render", rec, ""}), "OUT.png: empty path"));
  CHECK(contains(refused({"render", rec, tmp.path().string()}), tmp.path().string() + ": is a folder, expected a .png file path"));
  CHECK(entries(tmp.path()) == before);
}

TEST_CASE("catalogue: render refuses an image over 100 megapixels", "[cli][refusal][catalogue]") {
  TempDir tmp;
  write_frames(tmp / "long", 256);
  const std::string png = (tmp / "x.png").string();
  CHECK(contains(refused({"render", (tmp / "long").string(), png, "--contact-sheet", "--count", "256", "--columns", "16",
                     "--scale", "64"}),
            png + ": the image would be 26496x18304 pixels; lower --scale or --count"));
  CHECK(entries(tmp.path()) == std::set<std::string>{"long"});
}

TEST_CASE("catalogue: render --compare with fewer frames", "[cli][refusal][catalogue]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  write_frames(tmp / "short", 4);
  const std::string rec = (tmp / "rec").string(), short_rec = (tmp / "short").string(), png = (tmp / "x.png").string();
  const std::set<std::string> before = entries(tmp.path());
  CHECK(contains(refused({"render", rec, png, "--compare", short_rec, "--contact-sheet"}),
            "--compare " + short_rec + ": 4 frames but " + rec + " has 12 (a contact sheet compares the same frames)"));
  CHECK(contains(refused({"render", rec, png, "--compare", short_rec, "--frame", "8"}),
            short_rec + ": --frame 8: out of range (4 frames, 0 to 3)"));
  CHECK(entries(tmp.path()) == before);
}

// ---- bolo simulate -------------------------------------------------------------------------------

TEST_CASE("catalogue: simulate option values", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const std::string out = (tmp / "sim").string();
  CHECK(contains(refused({"simulate", out, "--size", "4x4"}), "--size: 4x4 is outside 8x8 .. 4096x4096"));
  CHECK(contains(refused({"simulate", out, "--frames", "0"}), "--frames: must be at least 1"));
  CHECK(contains(refused({"simulate", out, "--noise=-1"}), "--noise: must be >= 0, got -1"));
  CHECK(contains(refused({"simulate", out, "--tau-c", "0"}), "--tau-c: must be a positive number, got 0"));
  CHECK(contains(refused({"simulate", out, "--exposure", "0"}), "--exposure: must be a positive number, got 0"));
  CHECK(contains(refused({"simulate", out, "--tau", "0"}), "--tau: must be a positive number, got 0"));
  CHECK(contains(refused({"simulate", out, "--noise-1f=-2"}), "--noise-1f: must be >= 0, got -2"));
  CHECK(contains(refused({"simulate", out, "--substeps", "65"}), "--substeps"));
  CHECK(contains(refused({"simulate", out, "--fps", "30", "--exposure", "0.02", "--readout", "0.02"}),
            "--exposure + --readout: 0.04 s do not fit one frame period"));
  CHECK(contains(refused({"simulate", out, "--lag", "smooth"}), "--lag: expected exposure-readout or continuous, got 'smooth'"));
  CHECK(contains(refused({"simulate", out, "--lag", "continuous", "--exposure", "0.01"}),
            "--exposure, --readout: not with --lag continuous"));
  CHECK(contains(refused({"simulate", out, "--lag", "continuous", "--tau-h", "0.01", "--tau-c", "0.02"}),
            "--lag continuous has one time constant"));
  CHECK(contains(refused({"simulate", out, "--trajectory", "drive"}), "--trajectory drive: "));
  CHECK(contains(refused({"simulate"}), "no output folder: give OUT or --out"));
  CHECK(contains(refused({"simulate", out, "--out", out + "2"}), "OUT " + out + " and --out " + out + "2: give one"));
  CHECK(entries(tmp.path()).empty());
}

TEST_CASE("catalogue: simulate --effect specifications", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const std::string out = (tmp / "sim").string();
  CHECK(contains(refused({"simulate", out, "--effect", ":sigma=1"}), "--effect ':sigma=1': no effect id"));
  CHECK(contains(refused({"simulate", out, "--effect", "offset_fpn:sigma=1,sigma=2"}),
            "--effect 'offset_fpn:sigma=1,sigma=2': sigma given twice"));
  CHECK(contains(refused({"simulate", out, "--effect", "offset_fpn", "--effect", "offset_fpn"}), "--effect offset_fpn: given twice"));
  CHECK(contains(refused({"simulate", out, "--effect", "offset_fpn:sgima=1"}), "--effect offset_fpn: sgima: unknown parameter"));
  CHECK(contains(refused({"simulate", out, "--effect", "offset_fpn:sigma=abc"}), "--effect offset_fpn: sigma: not a number: 'abc'"));
  CHECK(contains(refused({"simulate", out, "--effect", "ffc_step"}), "--effect ffc_step: give every=N or frames=A/B/..."));
  CHECK(entries(tmp.path()).empty());
}

TEST_CASE("catalogue: simulate OUT that exists, is not a recording, or has no parent", "[cli][refusal][catalogue]") {
  TempDir tmp;
  const auto sim = [&](const fs::path& out, bool overwrite) {
    std::vector<std::string> args = {"simulate", out.string(), "--frames", "2", "--size", "8x8"};
    if (overwrite) args.push_back("--overwrite");
    return args;
  };
  REQUIRE(run_bolo(sim(tmp / "done", false)).code == 0);
  const std::string before = read_text(tmp / "done" / "frames.npy");
  CHECK(contains(refused(sim(tmp / "done", false)), (tmp / "done").string() + ": already exists (use --overwrite to replace it)"));
  CHECK(read_text(tmp / "done" / "frames.npy") == before);
  std::ofstream(tmp / "file") << "keep";
  CHECK(contains(refused(sim(tmp / "file", true)), (tmp / "file").string() + ": exists and is not a folder; refusing to replace it"));
  fs::create_directory(tmp / "docs");
  std::ofstream(tmp / "docs" / "keep.txt") << "keep";
  CHECK(contains(refused(sim(tmp / "docs", true)),
            (tmp / "docs").string() + ": exists and is not a recording folder (no recording.json); refusing to replace it"));
  CHECK(contains(refused(sim(tmp / "no" / "sim", false)),
            (tmp / "no" / "sim").string() + ": the parent folder " + (tmp / "no").string() + " does not exist"));
  CHECK(contains(refused(sim(tmp / "docs" / ".", true)), "output folder '" + (tmp / "docs" / ".").string() + "': not a valid destination name"));
  CHECK(read_text(tmp / "file") == "keep");
  CHECK(read_text(tmp / "docs" / "keep.txt") == "keep");
  CHECK(entries(tmp.path()) == std::set<std::string>{"done", "file", "docs"});
  CHECK(entries(tmp / "docs") == std::set<std::string>{"keep.txt"});
}

// ---- Negative numbers for unsigned options -----------------------------------------------------
// CLI11 reads "-1" into a 64-bit unsigned option as 2^64 - 1; the commands check the sign first
// (`not_negative()` in registry.hpp), so the message names the flag and the value typed.

TEST_CASE("catalogue: a negative count is refused as typed, not wrapped to 2^64 - 1", "[cli][refusal][catalogue]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::string err = refused({"render", (tmp / "rec").string(), (tmp / "x.png").string(), "--frame", "-1"});
  CHECK_FALSE(contains(err, "18446744073709551615"));
  CHECK(contains(err, "--frame: must not be negative, got -1"));
  const std::string sim = refused({"simulate", (tmp / "sim").string(), "--seed", "-5"});
  CHECK(contains(sim, "--seed: must not be negative, got -5"));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec"});
}
