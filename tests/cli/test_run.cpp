// bolo run: the firmware pipeline from a source into a sink. Into a recording it writes what
// `bolo correct` writes (a transfer log, a recording); raw:- is frames.npy's payload; SIGINT and
// SIGTERM in the middle of a run (the built binary, spawned) leave a whole, valid recording; the
// refusals name the flag, the device or the sink, and leave nothing behind.

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

#include <nlohmann/json.hpp>

#include "../hal/flirone_frames.hpp"
#include "bolo/hal/frame_sink.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/run/run_pipeline.hpp"
#include "cli_test_support.hpp"

extern char** environ;

using namespace bolo;
using namespace bolo::test;

namespace {

const std::vector<std::string> kTiming = {"--tau-h", "0.012", "--tau-c", "0.012", "--exposure", "0.01", "--readout", "0.1"};

CliResult bolo_run(const std::string& device, const std::string& sink, std::vector<std::string> more = {}) {
  std::vector<std::string> args = {"run", "--device", device, "--sink", sink};
  args.insert(args.end(), kTiming.begin(), kTiming.end());
  args.insert(args.end(), more.begin(), more.end());
  return run_bolo(args);
}

CliResult bolo_correct(const std::string& source, const fs::path& out) {
  std::vector<std::string> args = {"correct", source, out.string(), "--no-progress"};
  args.insert(args.end(), kTiming.begin(), kTiming.end());
  return run_bolo(args);
}

// frames.npy without its header: the frames' bytes.
std::string npy_payload(const fs::path& npy) {
  return read_text(npy).substr(rec::read_npy_header(npy).data_offset);
}

// `bolo run --device SPEC --sink recording:` writes the frames.npy and frames.csv of `bolo correct SPEC`.
void run_equals_correct(const std::string& spec, const TempDir& tmp) {
  const CliResult corrected = bolo_correct(spec, tmp / "corrected");
  INFO(corrected.err);
  REQUIRE(corrected.code == 0);
  const CliResult ran = bolo_run(spec, "recording:" + (tmp / "ran").string());
  INFO(ran.err);
  REQUIRE(ran.code == 0);
  CHECK(ran.out.empty());  // everything it says goes to stderr
  CHECK(read_text(tmp / "ran" / "frames.npy") == read_text(tmp / "corrected" / "frames.npy"));
  CHECK(read_text(tmp / "ran" / "frames.csv") == read_text(tmp / "corrected" / "frames.csv"));
  const auto info = nlohmann::json::parse(read_text(tmp / "ran" / "recording.json"));
  CHECK(info.at("correction").at("tool") == "bolo run");
  CHECK(contains(ran.err, "corrected " + spec + " -> recording:" + (tmp / "ran").string()));
  CHECK(contains(ran.err, "  ended         the source has no more frames"));
  CHECK(contains(ran.err, "  latency       median "));
}

}  // namespace

TEST_CASE("run: the real FLIR ONE transfer log into a recording equals bolo correct's", "[cli][run][real]") {
  const fs::path log = shared_folder("usb/flirone-pro", "1.txt");
  if (log.empty()) return;
  TempDir tmp;
  run_equals_correct("flirone-log:" + log.string(), tmp);
  CHECK(fs::exists(tmp / "ran" / "capture.json"));
  CHECK(rec::Recording(tmp / "ran").frame_count() == 20);
  // raw:- on stdout is frames.npy's payload.
  const CliResult raw = bolo_run("flirone-log:" + log.string(), "raw:-");
  INFO(raw.err);
  REQUIRE(raw.code == 0);
  CHECK(raw.out.size() == std::size_t{20} * 80 * 60 * 2);
  CHECK(raw.out == npy_payload(tmp / "corrected" / "frames.npy"));
}

TEST_CASE("run: the real lepton3-possum recording (file:) into a recording equals bolo correct's",
          "[cli][run][real]") {
  const fs::path dir = shared_recording("lepton3-possum");
  if (dir.empty()) return;
  TempDir tmp;
  run_equals_correct("file:" + dir.string(), tmp);
  CHECK(rec::Recording(tmp / "ran").frame_count() == 160);
}

TEST_CASE("run: a transfer log with a fault, into a recording and to raw:-", "[cli][run]") {
  TempDir tmp;
  write_flirone_log(tmp / "log", 10, {5});
  const std::string spec = "flirone-log:" + (tmp / "log").string();
  run_equals_correct(spec, tmp);
  const CliResult raw = bolo_run(spec, "raw:-");
  INFO(raw.err);
  REQUIRE(raw.code == 0);
  CHECK(raw.out == npy_payload(tmp / "corrected" / "frames.npy"));
  CHECK(contains(raw.err, "input         live source: 1 faulted frames skipped"));
  CHECK(contains(raw.err, "frames        9: "));
  // --frames stops early; the recording holds just those.
  REQUIRE(bolo_run(spec, "recording:" + (tmp / "three").string(), {"--frames", "3"}).code == 0);
  CHECK(rec::Recording(tmp / "three").frame_count() == 3);
}

TEST_CASE("run: a recording (file:REC) equals bolo correct of it", "[cli][run]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::string spec = "file:" + (tmp / "rec").string();
  run_equals_correct(spec, tmp);
  CHECK_FALSE(fs::exists(tmp / "ran" / "capture.json"));  // a recording has no device counters
  CHECK(contains(refused({"run", "--device", spec, "--sink", "recording:" + (tmp / "rec").string(), "--tau-h",
                          "0.012", "--tau-c", "0.012", "--overwrite"}),
                 "--sink recording:" + (tmp / "rec").string() + ": is the input recording; write elsewhere"));
}

TEST_CASE("run: refusals name the flag, device or sink and leave nothing behind", "[cli][run]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::string rec = "file:" + (tmp / "rec").string();
  const std::string out = "recording:" + (tmp / "out").string();
  CHECK(contains(refused(with({"run", "--device", rec, "--sink", "nosuch:x"}, kTiming)),
                 "--sink nosuch:x: unknown sink (expected recording:DIR, raw:- or v4l2:/dev/videoN)"));
  CHECK(contains(refused(with({"run", "--device", rec, "--sink", "raw:out.y16"}, kTiming)),
                 "--sink raw:out.y16: raw: needs - (the standard output): raw:-"));
  CHECK(contains(refused(with({"run", "--device", rec, "--sink", "recording:"}, kTiming)),
                 "--sink recording:: recording: needs a folder, e.g. recording:out/run"));
  CHECK(contains(refused(with({"run", "--device", (tmp / "rec").string(), "--sink", out}, kTiming)),
                 "--device " + (tmp / "rec").string() + ": unknown device (expected "));
  CHECK(contains(refused(with({"run", "--device", "usb:boson", "--sink", out}, kTiming)),
                 "--device usb:boson: unknown USB camera 'boson'"));
  CHECK(contains(refused({"run", "--device", rec, "--sink", out, "--tau-h", "0", "--tau-c", "0.012"}),
                 "--tau-h 0: must be a finite time in seconds, > 0"));
  fs::create_directories(tmp / "exists");
  CHECK(contains(refused(with({"run", "--device", rec, "--sink", "recording:" + (tmp / "exists").string()}, kTiming)),
                 (tmp / "exists").string() + ": already exists (use --overwrite to replace it)"));
  write_flirone_log(tmp / "bad", 6, {0, 1, 2, 3, 4});
  CHECK(contains(refused(with({"run", "--device", "flirone-log:" + (tmp / "bad").string(), "--sink", out,
                               "--max-faults", "3"},
                              kTiming)),
                 "/bad: gave up after 3 faults in a row, 0 frames corrected, nothing written (timeouts 0"));
  const std::set<std::string> left = entries(tmp.path());
  CHECK(left == std::set<std::string>{"rec", "exists", "bad"});
}

TEST_CASE("run: the v4l2 sink refuses what is not a V4L2 output device, naming it", "[cli][run][v4l2]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const std::string rec = "file:" + (tmp / "rec").string();
  { std::ofstream(tmp / "plain-file") << "not a device"; }
  const std::string file = (tmp / "plain-file").string();
  CHECK(contains(refused(with({"run", "--device", rec, "--sink", "v4l2:" + file}, kTiming)),
                 "--sink v4l2:" + file + ": " + file + ": not a V4L2 device"));
  CHECK(contains(refused(with({"run", "--device", rec, "--sink", "v4l2:/dev/null"}, kTiming)),
                 "--sink v4l2:/dev/null: /dev/null: not a V4L2 device"));
  const std::string missing = (tmp / "no-such-node").string();
  CHECK(contains(refused(with({"run", "--device", rec, "--sink", "v4l2:" + missing}, kTiming)),
                 "--sink v4l2:" + missing + ": " + missing + ": cannot open: No such file or directory"));
  CHECK(contains(refused(with({"run", "--device", rec, "--sink", "v4l2:"}, kTiming)),
                 "--sink v4l2:: v4l2: needs a V4L2 output device node, e.g. v4l2:/dev/video10"));
  // The library says the same without the flag.
  hal::SinkSetup setup;
  setup.info.width = 24;
  setup.info.height = 16;
  CHECK_THROWS_WITH(hal::open_sink("v4l2:" + file, setup), "v4l2:" + file + ": " + file + ": not a V4L2 device");
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec", "plain-file"});
}

// A camera that has stopped sending: every attempt times out.
class SilentSource final : public hal::FrameSource {
 public:
  hal::SourceFormat format() const override { return {.width = 4, .height = 2}; }
  hal::StreamStatus stream_frame(fw::LineSink&) override {
    std::this_thread::sleep_for(std::chrono::milliseconds(400));  // a device's timeout, shortened
    ++stats_.timeouts;
    return hal::StreamStatus::fault;
  }
  hal::SourceStats stats() const override { return stats_; }

 private:
  hal::SourceStats stats_;
};

TEST_CASE("run: a source that times out still reports each second, and a stop ends the run, nothing written", "[cli][run][signal]") {
  hal::SourceBackend silent;
  silent.scheme = "silent-test";
  silent.summary = "a camera that sends nothing (tests)";
  silent.open = [](const std::string&, const hal::SourceOptions&) {
    return std::make_unique<hal::OpenedSource>(std::make_unique<SilentSource>(), "silent");
  };
  hal::register_source(silent);
  TempDir tmp;
  run::RunRequest request;
  request.input = "silent-test";
  request.sink = "recording:" + (tmp / "out").string();
  request.tau_h_s = request.tau_c_s = 0.012;
  int asked = 0;
  std::ostringstream out, status;
  // The stop comes after a few timeouts, long before --max-faults (50) would give up.
  const run::RunResult result =
      run::run_pipeline(request, {}, out, status, [&asked] { return ++asked > 3 ? SIGINT : 0; });
  CHECK(result.stopped_by == SIGINT);
  CHECK(result.correction.frames == 0);
  CHECK(result.correction.skipped == 3);
  // Silent for over a second: a status line all the same.
  CHECK(contains(status.str(), "run 1 s: 0.0 fps, no frame, faults 3, carry-over breaks 0 (0 frames)"));
  CHECK_FALSE(result.written);
  CHECK(entries(tmp.path()).empty());
}

TEST_CASE("run: help names the sinks, the raw format and a GStreamer pipeline", "[cli][run][help]") {
  const CliResult r = run_bolo({"run", "--help"});
  CHECK(r.code == 0);
  for (const char* part : {"--device", "--sink", "--frames", "--real-time", "recording:DIR", "raw:-", "v4l2:/dev/videoN",
                           "little-endian", "gst-launch-1.0 fdsrc", "rawvideoparse format=gray16-le"})
    CHECK(contains(r.out, part));
}

// The built binary, spawned: a signal in the middle of a run replayed at its frame times.
namespace {

// 100 frames 50 ms apart: 5 s at --real-time.
void write_long_recording(const fs::path& dir) {
  rec::RecordingInfo info;
  info.sensor = "test sensor";
  info.width = SmallRecording::kWidth;
  info.height = SmallRecording::kHeight;
  info.bits = 14;
  info.fps = 20;
  rec::RecordingWriter writer(dir, info);
  for (std::uint64_t i = 0; i < 100; ++i) {
    rec::FrameRow row = SmallRecording::row(i % SmallRecording::kFrames);
    row.t_s = 0.05 * static_cast<double>(i);
    row.ffc = false;
    writer.append(SmallRecording::frame(i % SmallRecording::kFrames), row);
  }
  writer.commit();
}

struct Spawned {
  pid_t pid = -1;
};

Spawned spawn_bolo(const std::vector<std::string>& args, const fs::path& out, const fs::path& err) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> all = {BOLO_EXECUTABLE};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  Spawned s;
  const int rc = posix_spawn(&s.pid, BOLO_EXECUTABLE, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(rc == 0);
  return s;
}

// Waits up to `limit` for `part` to appear in `file`.
bool wait_for_text(const fs::path& file, const std::string& part, std::chrono::seconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    if (read_text(file).find(part) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// The exit status, or -1 if it did not exit within `limit` (then it is killed).
int wait_for_exit(pid_t pid, std::chrono::seconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (std::chrono::steady_clock::now() < until) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

}  // namespace

TEST_CASE("run: SIGINT or SIGTERM mid-run leaves a whole, valid recording and exits 0", "[cli][run][signal]") {
  TempDir tmp;
  write_long_recording(tmp / "rec");
  const std::string spec = "file:" + (tmp / "rec").string();
  REQUIRE(bolo_correct(spec, tmp / "corrected").code == 0);
  rec::Recording corrected(tmp / "corrected");
  for (const int signal : {SIGINT, SIGTERM}) {
    const std::string name = signal == SIGINT ? "SIGINT" : "SIGTERM";
    INFO(name);
    const fs::path out = tmp / ("ran-" + name);
    std::vector<std::string> args = {"run", "--device", spec, "--sink", "recording:" + out.string(), "--real-time"};
    args.insert(args.end(), kTiming.begin(), kTiming.end());
    const Spawned bolo = spawn_bolo(args, tmp / "stdout", tmp / "stderr");
    // The first status line comes after a second: some 20 frames in, some 80 to go.
    const bool running = wait_for_text(tmp / "stderr", "run 1 s: ", std::chrono::seconds(30));
    kill(bolo.pid, signal);
    const int code = wait_for_exit(bolo.pid, std::chrono::seconds(30));
    const std::string err = read_text(tmp / "stderr");
    INFO(err);
    REQUIRE(running);
    CHECK(code == 0);
    CHECK(contains(err, " fps, latency median "));
    CHECK(contains(err, "  stopped       by " + name + " after "));
    CHECK(read_text(tmp / "stdout").empty());
    rec::Recording ran(out);  // validates recording.json, frames.npy, frames.csv
    CHECK(ran.frame_count() > 0);
    CHECK(ran.frame_count() < 100);
    for (std::uint64_t i = 0; i < ran.frame_count(); ++i) {
      CHECK(read_u16_frame(ran, i) == read_u16_frame(corrected, i));
      CHECK(ran.rows()[i].t_s == corrected.rows()[i].t_s);
    }
    CHECK(contains(err, "frames        " + std::to_string(ran.frame_count()) + ": "));
  }
  // Nothing else is left beside the recordings: no hidden temporary folder.
  CHECK(entries(tmp.path()) ==
        std::set<std::string>{"rec", "corrected", "ran-SIGINT", "ran-SIGTERM", "stdout", "stderr"});
}

TEST_CASE("correct and run: --nuc applies each pixel's gain and offset first", "[cli][run][nuc]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  // The same recording with every pixel 10 counts higher: what a NUC of gain 1, offset 10 makes.
  {
    rec::Recording source(tmp / "rec");
    rec::RecordingWriter writer(tmp / "rec+10", source.info());
    for (std::uint64_t i = 0; i < source.frame_count(); ++i) {
      std::vector<std::uint16_t> frame = read_u16_frame(source, i);
      for (std::uint16_t& p : frame) p = static_cast<std::uint16_t>(p + 10);
      writer.append(frame, source.rows()[i]);
    }
    writer.commit();
  }
  constexpr std::uint64_t kW = SmallRecording::kWidth, kH = SmallRecording::kHeight;
  const auto write_nuc = [&](const std::string& name, std::vector<std::uint64_t> shape, float gain, float offset) {
    std::vector<float> planes(shape[0] * shape[1] * shape[2], offset);
    std::fill(planes.begin(), planes.begin() + static_cast<std::ptrdiff_t>(shape[1] * shape[2]), gain);
    std::ofstream(tmp / name, std::ios::binary) << rec::encode_npy_f4(shape, planes);
    return (tmp / name).string();
  };
  const std::string nuc = write_nuc("nuc.npy", {2, kH, kW}, 1.0F, 10.0F);
  const std::string rec = (tmp / "rec").string();
  for (const bool float_output : {false, true}) {
    INFO("--float " << float_output);
    const std::vector<std::string> flt = float_output ? std::vector<std::string>{"--float"} : std::vector<std::string>{};
    const std::string suffix = float_output ? "-float" : "";
    REQUIRE(run_bolo(with(with({"correct", rec, (tmp / ("nuc-out" + suffix)).string(), "--nuc", nuc, "--no-progress"},
                               kTiming), flt)).code == 0);
    REQUIRE(run_bolo(with(with({"correct", (tmp / "rec+10").string(), (tmp / ("plus-out" + suffix)).string(),
                                "--no-progress"}, kTiming), flt)).code == 0);
    CHECK(read_text(tmp / ("nuc-out" + suffix) / "frames.npy") == read_text(tmp / ("plus-out" + suffix) / "frames.npy"));
  }
  REQUIRE(bolo_run("file:" + rec, "recording:" + (tmp / "run-out").string(), {"--nuc", nuc}).code == 0);
  CHECK(read_text(tmp / "run-out" / "frames.npy") == read_text(tmp / "plus-out" / "frames.npy"));
  CHECK(nlohmann::json::parse(read_text(tmp / "run-out" / "recording.json")).at("correction").at("nuc") == nuc);
  // Refusals name the flag, the file and the pixel; nothing is written.
  const std::string wide = write_nuc("wide.npy", {2, kH, kW + 1}, 1.0F, 0.0F);
  CHECK(contains(refused(with({"run", "--device", "file:" + rec, "--sink", "recording:" + (tmp / "x").string(),
                               "--nuc", wide}, kTiming)),
                 "--nuc " + wide + ": shape (2, 16, 25), expected (2, 16, 24): each pixel's gain, then its offset"));
  const std::string hot = write_nuc("hot.npy", {2, kH, kW}, 5.0F, 0.0F);
  CHECK(contains(refused(with({"correct", rec, (tmp / "x").string(), "--nuc", hot}, kTiming)),
                 "--nuc " + hot + ": gain at pixel (0, 0): 5 is outside 0 .. 3.99994 (the firmware's Q2.14)"));
  const std::string far = write_nuc("far.npy", {2, kH, kW}, 1.0F, 40000.0F);
  CHECK(contains(refused(with({"correct", rec, (tmp / "x").string(), "--nuc", far}, kTiming)),
                 "--nuc " + far + ": offset at pixel (0, 0): 40000 is outside -32768 .. 32767 counts"));
  const std::string missing = (tmp / "none.npy").string();
  CHECK(contains(refused(with({"correct", rec, (tmp / "x").string(), "--nuc", missing}, kTiming)),
                 "--nuc " + missing + ": cannot open"));
  CHECK_FALSE(fs::exists(tmp / "x"));
}
