// Every refusal: exit code 2, one line `bolo: error: ...` naming the file, frame, field or flag,
// and no output left behind (the test folder holds exactly what it held before).

#include <catch2/catch.hpp>

#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

const std::set<std::string> kOnlyRec = {"rec"};

}  // namespace

TEST_CASE("refuse: missing exposure, naming file, frame and field", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec", [](std::uint64_t i) { return i != 0; });
  const std::string err = refused(correct_args(tmp));
  CHECK(contains(err, (tmp / "rec" / "frames.csv").string() + ": frame 0: field exposure_s: empty and no --exposure given"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: missing readout in a later frame, even with --exposure", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec", [](std::uint64_t i) { return i != 7; });
  const std::string err = refused(with(correct_args(tmp), {"--exposure", "0.01"}));
  CHECK(contains(err, "frames.csv: frame 7: field readout_s: empty and no --readout given"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: tau <= 0 names the flag", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  CHECK(contains(refused({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "0", "--tau-c", "0.012"}),
                 "--tau-h 0: must be a finite time in seconds, > 0"));
  CHECK(contains(refused({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "0.012", "--tau-c=-0.5"}),
                 "--tau-c -0.5: must be"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: NaN and infinite tau name the flag", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  CHECK(contains(refused({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "0.012", "--tau-c", "nan"}),
                 "--tau-c"));
  CHECK(contains(refused({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "inf", "--tau-c", "0.012"}),
                 "--tau-h"));
  // The library function refuses the same way (tests and other callers skip CLI11).
  cli::CorrectOptions o;
  o.input = tmp / "rec";
  o.output = tmp / "out";
  o.tau_h_s = 0.012;
  o.tau_c_s = std::nan("");
  std::ostringstream out;
  CHECK_THROWS_WITH(cli::run_correct(o, out), Catch::Contains("--tau-c nan"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: unusable coefficients name the values", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  // t_e / tau_h = 0.008 / 3 is below ~0.004: the gain would exceed 256.
  const std::string err = refused({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "3", "--tau-c", "0.012"});
  CHECK(contains(err, "frame 0: no usable coefficients (gain_out_of_range)"));
  CHECK(contains(err, "exposure 0.008 s (field exposure_s) with --tau-h 3 --tau-c 0.012"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: a recording folder that does not exist, in every command", "[cli][refusal]") {
  TempDir tmp;
  const std::string missing = (tmp / "nope").string();
  CHECK(contains(refused({"info", missing}), missing + ": no such recording folder"));
  CHECK(contains(refused(with(correct_args(tmp, "nope"), {"--exposure", "0.01", "--readout", "0.01"})),
                 missing + ": no such recording folder"));
  CHECK(contains(refused({"render", missing, (tmp / "x.png").string()}), missing + ": no such recording folder"));
  CHECK(entries(tmp.path()).empty());
}

TEST_CASE("refuse: existing OUT without --overwrite, and --overwrite replaces only recordings", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  REQUIRE(run_bolo(correct_args(tmp)).code == 0);
  const std::string before = read_text(tmp / "out" / "frames.npy");
  // Different constants, so a replaced output would differ.
  const std::string err = refused({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "0.02", "--tau-c", "0.02"});
  CHECK(contains(err, (tmp / "out").string() + ": already exists (use --overwrite to replace it)"));
  CHECK(read_text(tmp / "out" / "frames.npy") == before);
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec", "out"});

  // --overwrite replaces a recording...
  REQUIRE(run_bolo({"correct", (tmp / "rec").string(), (tmp / "out").string(), "--tau-h", "0.02", "--tau-c", "0.02",
                    "--overwrite"}).code == 0);
  CHECK(read_text(tmp / "out" / "frames.npy") != before);
  // ...but never a folder that is not one, nor the input itself.
  fs::create_directory(tmp / "docs");
  std::ofstream(tmp / "docs" / "keep.txt") << "keep";
  CHECK(contains(refused(with(correct_args(tmp, "rec", "docs"), {"--overwrite"})), "is not a recording folder"));
  CHECK(fs::exists(tmp / "docs" / "keep.txt"));
  CHECK(contains(refused(with(correct_args(tmp, "rec", "rec"), {"--overwrite"})), "OUT is the input recording"));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec", "out", "docs"});
}

TEST_CASE("refuse: frame out of range names the frame", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::string err = refused({"render", (tmp / "rec").string(), (tmp / "x.png").string(), "--frame", "12"});
  CHECK(contains(err, (tmp / "rec").string() + ": --frame 12: out of range (12 frames, 0 to 11)"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: truncated frames.npy", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const fs::path npy = tmp / "rec" / "frames.npy";
  fs::resize_file(npy, fs::file_size(npy) - 100);
  for (const auto& args : {correct_args(tmp), std::vector<std::string>{"info", (tmp / "rec").string()},
                           std::vector<std::string>{"render", (tmp / "rec").string(), (tmp / "x.png").string()}})
    CHECK(contains(refused(args), npy.string()));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: a bad frames.csv cell names file, frame and field", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const fs::path csv = tmp / "rec" / "frames.csv";
  std::string text = read_text(csv);
  // Line 5 is frame 3: replace its t_s cell with junk.
  std::size_t pos = 0;
  for (int line = 0; line < 4; ++line) pos = text.find('\n', pos) + 1;
  const std::size_t comma = text.find(',', pos);
  const std::size_t next = text.find(',', comma + 1);
  text.replace(comma + 1, next - comma - 1, "abc");
  std::ofstream(csv, std::ios::binary | std::ios::trunc) << text;
  CHECK(contains(refused(correct_args(tmp)), csv.string() + ": frame 3: field t_s"));
  CHECK(contains(refused({"info", (tmp / "rec").string()}), csv.string() + ": frame 3: field t_s"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: bad render flags and mismatched --compare", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  {
    rec::RecordingInfo info;
    info.width = 8;
    info.height = 8;
    rec::RecordingWriter writer(tmp / "small", info);
    rec::FrameRow row;
    row.t_s = 0.0;
    writer.append(std::vector<std::uint16_t>(64, 100), row);
    writer.commit();
  }
  const std::string rec_dir = (tmp / "rec").string(), png = (tmp / "x.png").string();
  CHECK(contains(refused({"render", rec_dir, png, "--compare", (tmp / "small").string()}), "--compare"));
  CHECK(contains(refused({"render", rec_dir, png, "--range", "9:1"}), "--range 9:1"));
  CHECK(contains(refused({"render", rec_dir, png, "--range", "a:b"}), "--range a:b"));
  CHECK(contains(refused({"render", rec_dir, png, "--percentile", "5:150"}), "--percentile 5:150"));
  CHECK(contains(refused({"render", rec_dir, png, "--scale", "0"}), "--scale 0"));
  CHECK(contains(refused({"render", rec_dir, png, "--colormap", "rainbow"}), "--colormap"));
  CHECK(contains(refused({"render", rec_dir, png, "--frame", "1", "--contact-sheet"}), "--frame"));
  CHECK(contains(refused({"render", rec_dir, (tmp / "no" / "x.png").string()}), (tmp / "no" / "x.png").string()));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec", "small"});
}

TEST_CASE("refuse: a failure after the frames are written leaves no OUT and no temporary folder", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  // poses.tum is copied after every frame went through the pipeline into the writer's
  // temporary folder; a folder in its place fails that copy.
  fs::create_directory(tmp / "rec" / "poses.tum");
  CHECK(contains(refused(with(correct_args(tmp), {"--stats", (tmp / "stats.csv").string()})),
                 (tmp / "rec" / "poses.tum").string() + ": not a regular file"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: --stats into a missing folder, before anything is written", "[cli][refusal]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  CHECK(contains(refused(with(correct_args(tmp), {"--stats", (tmp / "no" / "s.csv").string()})), "--stats"));
  CHECK(entries(tmp.path()) == kOnlyRec);
}

TEST_CASE("refuse: usage errors exit 2 with one line", "[cli][refusal]") {
  TempDir tmp;
  CHECK(contains(refused({}), "subcommand"));
  CHECK(contains(refused({"frobnicate"}), "frobnicate: unknown command"));
  CHECK(contains(refused({"correct", "a", "b", "--tau-h", "1", "--tau-c", "1", "extra"}), "extra"));
  // Too long for the firmware's 32-bit nanoseconds.
  CHECK(contains(refused({"correct", "a", "b", "--tau-h", "5", "--tau-c", "1"}), "--tau-h 5: too long"));
  CHECK(contains(refused({"correct", (tmp / "rec").string()}), "bolo correct --help"));
  CHECK(contains(refused({"info", (tmp / "rec").string(), "--bogus"}), "--bogus"));
  CHECK(contains(refused({"correct", "a", "b", "--tau-h", "x", "--tau-c", "1"}), "--tau-h"));
  CHECK(entries(tmp.path()).empty());
}
