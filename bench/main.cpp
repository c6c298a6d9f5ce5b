// bolo-bench: throughput of the firmware's correction stages as ratios to memcpy measured in the
// same run, so that the figures mean something on a noisy, shared or unknown machine.
//
//   bolo-bench                      human-readable table, sizes 160x120, 640x512, 1280x1024
//   bolo-bench --json               one JSON object (see print_json)
//   bolo-bench --quick              few, short repetitions: a smoke run for CI, not a measurement
//   bolo-bench --sizes 160x120,640x512

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "harness.hpp"
#include "number_arg.hpp"
#include "scene.hpp"
#include "size_list.hpp"
#include "workloads.hpp"

namespace {

using namespace bolo::bench;

constexpr double kCorrectorGoal = 0.5;
constexpr double kPipelineGoal = 0.25;
// Bytes each workload moves per frame, in frames of width * height * 2 bytes.
constexpr double kMemcpyFramesMoved = 2.0;  // 1 read + 1 write
constexpr double kStageFramesMoved = 3.0;   // current + previous read, 1 written

struct Options {
  bool json = false;
  bool quick = false;
  bool help = false;
  std::vector<Size> sizes = {{160, 120}, {640, 512}, {1280, 1024}};
  int repetitions = 0;    // 0 = default for the mode
  double seconds = 0.0;   // per measurement; 0 = default for the mode
  std::string profile;    // non-empty: run only this workload, for perf / callgrind
  std::size_t input_frames = 4;  // distinct raw frames cycled through
};

constexpr const char* kUsage =
    "usage: bolo-bench [--json] [--quick] [--sizes WxH[,WxH...]] [--repetitions N] [--seconds S]\n"
    "                  [--input-frames N] [--profile memcpy|corrector|pipeline]\n"
    "\n"
    "Times the firmware's two-frame corrector and full pipeline (NUC -> bad pixels -> corrector)\n"
    "on synthetic 14-bit frames, interleaved with memcpy of a frame-sized buffer, and reports\n"
    "each stage's throughput as a ratio to memcpy's (bytes moved per second). Single-threaded.\n"
    "\n"
    "  --json            print one JSON object instead of the table\n"
    "  --quick           3 short repetitions (a smoke run for CI; figures are not meaningful)\n"
    "  --sizes LIST      frame sizes, e.g. 160x120,640x512 (default 160x120,640x512,1280x1024)\n"
    "  --repetitions N   repetitions per measurement; the median is reported (default 11)\n"
    "  --seconds S       approximate time per measurement, all repetitions (default 0.3)\n"
    "  --input-frames N  distinct raw frames cycled through (default 4); a large N makes the\n"
    "                    working set exceed the caches, as a camera's DMA'd frames do\n"
    "  --profile STAGE   run only memcpy|corrector|pipeline for --seconds on the first size and\n"
    "                    print its frame rate: a target for perf or valgrind, not a measurement\n"
    "  --help            this text\n"
    "\n"
    "Bytes moved per frame: memcpy 1 read + 1 write of the frame; corrector 2 frames read\n"
    "(current and previous) + 1 written; pipeline counted like the corrector (its NUC table and\n"
    "bad-pixel mask reads are not counted). Goals: corrector >= 0.5, pipeline >= 0.25 of memcpy.\n"
    "Exit status: 0 ok, 1 the run was invalid (carry-over not applied), 2 bad arguments.\n";

// Returns false (after a message on stderr) for a bad command line.
bool parse_options(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bolo-bench: %s needs a value\n", name);
        return nullptr;
      }
      return argv[++i];
    };
    if (arg == "--json") {
      o.json = true;
    } else if (arg == "--quick") {
      o.quick = true;
    } else if (arg == "--help" || arg == "-h") {
      o.help = true;
    } else if (arg == "--sizes") {
      const char* v = value("--sizes");
      if (v == nullptr) return false;
      if (!parse_size_list(v, o.sizes, "bolo-bench")) return false;
    } else if (arg == "--profile") {
      const char* v = value("--profile");
      if (v == nullptr) return false;
      o.profile = v;
      if (o.profile != "memcpy" && o.profile != "corrector" && o.profile != "pipeline") {
        std::fprintf(stderr, "bolo-bench: --profile wants memcpy, corrector or pipeline\n");
        return false;
      }
    } else if (arg == "--input-frames") {
      const char* v = value("--input-frames");
      if (v == nullptr || !parse_number_arg(v, o.input_frames, std::size_t{1}, std::size_t{256}, "bolo-bench", "--input-frames", "1..256"))
        return false;
    } else if (arg == "--repetitions") {
      const char* v = value("--repetitions");
      if (v == nullptr || !parse_number_arg(v, o.repetitions, 1, 1000, "bolo-bench", "--repetitions", "1..1000")) return false;
    } else if (arg == "--seconds") {
      const char* v = value("--seconds");
      if (v == nullptr || !parse_number_arg(v, o.seconds, 0.0, 600.0, "bolo-bench", "--seconds", "a number in (0, 600]", true))
        return false;
    } else {
      std::fprintf(stderr, "bolo-bench: unknown argument '%s' (try --help)\n", argv[i]);
      return false;
    }
  }
  if (o.repetitions == 0) o.repetitions = o.quick ? 3 : 11;
  if (o.seconds == 0.0) o.seconds = o.quick ? 0.02 : 0.3;
  return true;
}

struct Machine {
  std::string cpu = "unknown";
  unsigned logical_cpus = 0;
  // x86-64 ISA level the CPU supports: "x86-64-v4" (AVX-512), "x86-64-v3" (AVX2), "x86-64", or
  // "" elsewhere. The firmware's x86-64 kernels are built as clones for these levels.
  std::string isa;
};

Machine probe_machine() {
  Machine m;
  m.logical_cpus = std::thread::hardware_concurrency();
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) m.cpu = line.substr(line.find_first_not_of(" \t", colon + 1));
      break;
    }
  }
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
  __builtin_cpu_init();
  m.isa = __builtin_cpu_supports("x86-64-v4")   ? "x86-64-v4"
          : __builtin_cpu_supports("x86-64-v3") ? "x86-64-v3"
                                                : "x86-64";
#elif defined(__x86_64__)
  m.isa = "x86-64";
#endif
  return m;
}

struct Measurement {
  std::size_t frames_per_rep = 0;
  Series frames;  // frames per second, one entry per repetition
};

struct SizeResult {
  Size size;
  Measurement memcpy_, corrector, pipeline;
  std::uint64_t timed_stage_frames = 0;  // corrector + pipeline frames timed, all with carry-over
};

// Times one size: memcpy, corrector and pipeline alternate within every repetition (the order
// reverses on odd repetitions) so slow phases of a shared machine hit all three alike.
bool run_size(const Options& o, Size size, SizeResult& r) {
  const BenchData data = make_bench_data(size.width, size.height, o.input_frames);
  MemcpyWorkload mem(data);
  CorrectorWorkload cor(data);
  PipelineWorkload pipe(data);

  const double rep_s = o.seconds / o.repetitions;
  const double probe_s = std::min(0.01, rep_s / 2);
  const std::size_t min_frames = o.quick ? 1 : 3;
  Workload* work[3] = {&mem, &cor, &pipe};
  Measurement* meas[3] = {&r.memcpy_, &r.corrector, &r.pipeline};
  for (int k = 0; k < 3; ++k) {
    work[k]->run(1);  // fault pages in, warm caches and branch predictors
    meas[k]->frames_per_rep = calibrate(*work[k], rep_s, probe_s, min_frames);
  }
  for (int rep = 0; rep < o.repetitions; ++rep) {
    for (int j = 0; j < 3; ++j) {
      const int k = rep % 2 == 0 ? j : 2 - j;
      const double t = std::max(time_frames(*work[k], meas[k]->frames_per_rep), 1e-9);
      meas[k]->frames.per_s.push_back(static_cast<double>(meas[k]->frames_per_rep) / t);
    }
  }
  r.size = size;
  r.timed_stage_frames = (r.corrector.frames_per_rep + r.pipeline.frames_per_rep) *
                         static_cast<std::uint64_t>(o.repetitions);
  bool ok = true;
  if (cor.not_applied() != 0 || pipe.not_applied() != 0) {
    std::fprintf(stderr,
                 "bolo-bench: %s: carry-over was not applied on %llu corrector and %llu pipeline "
                 "frames; the figures would not measure the two-frame correction\n",
                 size.label().c_str(), static_cast<unsigned long long>(cor.not_applied()),
                 static_cast<unsigned long long>(pipe.not_applied()));
    ok = false;
  }
  clobber_memory(&cor);  // the checksums are live: the sinks' work is observable
  clobber_memory(&pipe);
  return ok;
}

struct Figures {
  double px_per_s, bytes_per_s, ratio, iqr_rel;
};

Figures figures(const Measurement& m, const Measurement& memcpy_m, Size s, double frames_moved) {
  const double px = static_cast<double>(s.width) * s.height;
  const double frame_bytes = px * sizeof(std::uint16_t);
  const double fps = m.frames.median_per_s();
  const double memcpy_bytes = memcpy_m.frames.median_per_s() * frame_bytes * kMemcpyFramesMoved;
  const double bytes = fps * frame_bytes * frames_moved;
  return {fps * px, bytes, memcpy_bytes > 0 ? bytes / memcpy_bytes : 0.0, m.frames.iqr_rel()};
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

void print_json(const Options& o, const Machine& m, const std::vector<SizeResult>& results) {
  auto stage = [&](const char* name, bool is_pipeline, double goal) {
    std::printf("  \"%s\": {", name);
    for (std::size_t i = 0; i < results.size(); ++i) {
      const SizeResult& r = results[i];
      const Measurement& meas = is_pipeline ? r.pipeline : r.corrector;
      const Figures f = figures(meas, r.memcpy_, r.size, kStageFramesMoved);
      std::printf(
          "%s\n    \"%s\": {\"px_per_s\": %.6g, \"bytes_per_s\": %.6g, \"ratio_to_memcpy\": %.4f, "
          "\"goal\": %.2f, \"meets_goal\": %s, \"frames_per_repetition\": %zu, \"iqr_rel\": %.4f}",
          i == 0 ? "" : ",", r.size.label().c_str(), f.px_per_s, f.bytes_per_s, f.ratio, goal,
          f.ratio >= goal ? "true" : "false", meas.frames_per_rep, f.iqr_rel);
    }
    std::printf("\n  },\n");
  };
  std::printf("{\n");
  stage("corrector", false, kCorrectorGoal);
  stage("pipeline", true, kPipelineGoal);
  std::printf("  \"memcpy\": {");
  for (std::size_t i = 0; i < results.size(); ++i) {
    const SizeResult& r = results[i];
    const Figures f = figures(r.memcpy_, r.memcpy_, r.size, kMemcpyFramesMoved);
    std::printf("%s\n    \"%s\": {\"bytes_per_s\": %.6g, \"px_per_s\": %.6g, "
                "\"frames_per_repetition\": %zu, \"iqr_rel\": %.4f}",
                i == 0 ? "" : ",", r.size.label().c_str(), f.bytes_per_s, f.px_per_s,
                r.memcpy_.frames_per_rep, f.iqr_rel);
  }
  std::printf("\n  },\n");
  std::printf("  \"bytes_moved_per_frame\": {\"memcpy\": \"1 frame read + 1 written\", "
              "\"corrector\": \"2 frames read + 1 written\", \"pipeline\": \"counted as the "
              "corrector: 2 frames read + 1 written (NUC tables and bad-pixel mask not counted)\"},\n");
  std::printf("  \"settings\": {\"repetitions\": %d, \"statistic\": \"median\", "
              "\"seconds_per_measurement\": %.3g, \"input_frames\": %zu, \"quick\": %s},\n",
              o.repetitions, o.seconds, o.input_frames, o.quick ? "true" : "false");
  std::printf("  \"machine\": {\"cpu\": %s, \"logical_cpus\": %u, \"isa\": %s}\n",
              json_string(m.cpu).c_str(), m.logical_cpus, json_string(m.isa).c_str());
  std::printf("}\n");
}

void print_table(const Options& o, const Machine& m, const std::vector<SizeResult>& results) {
  std::printf("bolo-bench: single-threaded throughput, as ratios to memcpy timed in the same run\n");
  std::printf("machine: %s, %u logical CPUs%s%s\n", m.cpu.c_str(), m.logical_cpus,
              m.isa.empty() ? "" : ", ISA level ", m.isa.c_str());
  std::printf("median of %d repetitions, ~%.2g s per measurement, %zu input frames cycled%s\n\n",
              o.repetitions, o.seconds, o.input_frames, o.quick ? " (--quick: a smoke run, not a measurement)" : "");
  std::printf("%-10s %-10s %10s %10s %10s %9s %-15s %6s\n", "size", "stage", "frames/s", "Mpx/s",
              "GB/s", "ratio", "goal", "noise");
  for (const SizeResult& r : results) {
    const std::string label = r.size.label();
    const Figures mf = figures(r.memcpy_, r.memcpy_, r.size, kMemcpyFramesMoved);
    std::printf("%-10s %-10s %10.1f %10.1f %10.2f %9.3f %-15s %5.1f%%\n", label.c_str(), "memcpy",
                r.memcpy_.frames.median_per_s(), mf.px_per_s / 1e6, mf.bytes_per_s / 1e9, 1.0,
                "(yardstick)", mf.iqr_rel * 100);
    auto row = [&](const char* name, const Measurement& meas, double goal) {
      const Figures f = figures(meas, r.memcpy_, r.size, kStageFramesMoved);
      char goal_text[32];
      std::snprintf(goal_text, sizeof goal_text, ">= %.2f %s", goal, f.ratio >= goal ? "PASS" : "BELOW");
      std::printf("%-10s %-10s %10.1f %10.1f %10.2f %9.3f %-15s %5.1f%%\n", "", name,
                  meas.frames.median_per_s(), f.px_per_s / 1e6, f.bytes_per_s / 1e9, f.ratio,
                  goal_text, f.iqr_rel * 100);
    };
    row("corrector", r.corrector, kCorrectorGoal);
    row("pipeline", r.pipeline, kPipelineGoal);
  }
  std::uint64_t frames = 0;
  for (const SizeResult& r : results) frames += r.timed_stage_frames;
  std::printf(
      "\nratio  = stage bytes/s / memcpy bytes/s (medians). Bytes moved per frame: memcpy 1 read +\n"
      "         1 write of the frame; corrector 2 frames read (current, previous) + 1 written;\n"
      "         pipeline counted like the corrector (NUC tables and mask reads not counted).\n"
      "noise  = interquartile range of the repetitions / median.\n"
      "All %llu timed corrector/pipeline frames had carry-over applied.\n",
      static_cast<unsigned long long>(frames));
}

// --profile: one workload alone, so a profiler sees nothing else.
int run_profile(const Options& o) {
  const Size size = o.sizes.front();
  const BenchData data = make_bench_data(size.width, size.height, o.input_frames);
  std::optional<MemcpyWorkload> mem;
  std::optional<CorrectorWorkload> cor;
  std::optional<PipelineWorkload> pipe;
  Workload* w = nullptr;
  if (o.profile == "memcpy") w = &mem.emplace(data);
  if (o.profile == "corrector") w = &cor.emplace(data);
  if (o.profile == "pipeline") w = &pipe.emplace(data);
  const std::size_t frames = calibrate(*w, o.seconds, std::min(0.01, o.seconds / 2), 1);
  const double t = std::max(time_frames(*w, frames), 1e-9);
  std::printf("%s %s: %zu frames in %.3f s, %.1f frames/s, %.1f Mpx/s\n", o.profile.c_str(),
              size.label().c_str(), frames, t, static_cast<double>(frames) / t,
              static_cast<double>(frames) * size.width * size.height / t / 1e6);
  if ((cor && cor->not_applied() != 0) || (pipe && pipe->not_applied() != 0)) {
    std::fprintf(stderr, "bolo-bench: carry-over was not applied on every frame\n");
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse_options(argc, argv, o)) return 2;
  if (o.help) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (!o.profile.empty()) return run_profile(o);
  const Machine machine = probe_machine();
  std::vector<SizeResult> results;
  bool ok = true;
  for (const Size& s : o.sizes) {
    SizeResult r;
    ok = run_size(o, s, r) && ok;
    results.push_back(std::move(r));
  }
  if (!ok) return 1;
  if (o.json)
    print_json(o, machine, results);
  else
    print_table(o, machine, results);
  return 0;
}
