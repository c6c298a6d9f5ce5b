// bolo correct REC OUT --tau-h S --tau-c S ...: runs the firmware pipeline over a recording
//   RecordingPlayer -> Pipeline ([bad pixels] -> two-frame corrector) -> FrameCollector -> RecordingWriter
// or, with --float, the double-precision reference for the pixels (the pipeline still runs
// alongside for the per-frame decisions). Everything that can be checked is checked before
// anything is written; the writer is atomic, so a failure leaves no OUT behind.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>
#include <vector>

#include "bolo/commands.hpp"
#include "bolo/core/frame_collector.hpp"
#include "bolo/errors.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "bolo/frame_stack.hpp"
#include "bolo/hal/recording_player.hpp"
#include "bolo/progress.hpp"
#include "bolo/recording/frame_row_header.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/registry.hpp"
#include "bolo/sim/corrector_reference.hpp"

namespace bolo::cli {
namespace {

namespace fs = std::filesystem;

std::string seconds_text(double seconds) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.9g", seconds);
  return buffer;
}

// A time given on the command line, as firmware nanoseconds: finite, > 0, within uint32 ns.
std::uint32_t flag_ns(const char* flag, double seconds) {
  if (!std::isfinite(seconds) || !(seconds > 0))
    fail(flag, " ", seconds_text(seconds), ": must be a finite time in seconds, > 0");
  const double ns = std::round(seconds * 1e9);
  if (ns < 1) fail(flag, " ", seconds_text(seconds), ": below the firmware's 1 ns resolution");
  if (ns > 4294967295.0)
    fail(flag, " ", seconds_text(seconds), ": too long (the firmware takes at most 4.29 s)");
  return static_cast<std::uint32_t>(ns);
}

// Forwards every event to two sinks.
class Tee final : public fw::LineSink {
 public:
  Tee(fw::LineSink& a, fw::LineSink& b) : a_(a), b_(b) {}
  void begin_frame(const fw::FrameHeader& h) override {
    a_.begin_frame(h);
    b_.begin_frame(h);
  }
  void push_line(std::uint32_t row, fw::LineView line) override {
    a_.push_line(row, line);
    b_.push_line(row, line);
  }
  void end_frame() override {
    a_.end_frame();
    b_.end_frame();
  }

 private:
  fw::LineSink& a_;
  fw::LineSink& b_;
};

// The exposure and readout each frame is corrected with, resolved before anything runs.
struct FrameTiming {
  std::uint32_t exposure_ns = 0, readout_ns = 0;
  double exposure_s = 0, readout_s = 0;
  bool exposure_from_flag = false, readout_from_flag = false;
};

struct Defaults {
  std::optional<double> seconds;
  std::uint32_t ns = 0;
};

// One timing field of one frame: the frames.csv value (as the player converts it) wins, the flag
// fills in where the cell is empty (or 0, which the firmware reads as unknown).
void resolve_field(const std::optional<double>& cell, std::uint32_t cell_ns, const Defaults& flag,
                   const fs::path& csv, std::uint64_t frame, const char* field,
                   const char* flag_name, std::uint32_t& ns, double& seconds, bool& from_flag) {
  if (cell_ns != 0) {
    ns = cell_ns;
    seconds = *cell;
    from_flag = false;
    return;
  }
  if (flag.seconds) {
    ns = flag.ns;
    seconds = *flag.seconds;
    from_flag = true;
    return;
  }
  if (!cell)
    fail(csv.string(), ": frame ", frame, ": field ", field, ": empty and no ", flag_name, " given");
  fail(csv.string(), ": frame ", frame, ": field ", field, ": ", seconds_text(*cell),
       " s is zero for the firmware (unknown) and no ", flag_name, " given");
}

std::vector<FrameTiming> resolve_timing(const rec::Recording& recording, const fs::path& csv,
                                        const Defaults& exposure, const Defaults& readout) {
  std::vector<FrameTiming> timing(recording.frame_count());
  for (std::size_t i = 0; i < timing.size(); ++i) {
    const rec::FrameRow& row = recording.rows()[i];
    const fw::FrameHeader header =
        rec::header_from_row(row, recording.width(), recording.height(), csv);
    FrameTiming& t = timing[i];
    resolve_field(row.exposure_s, header.exposure_ns, exposure, csv, i, "exposure_s", "--exposure",
                  t.exposure_ns, t.exposure_s, t.exposure_from_flag);
    resolve_field(row.readout_s, header.readout_ns, readout, csv, i, "readout_s", "--readout",
                  t.readout_ns, t.readout_s, t.readout_from_flag);
  }
  return timing;
}

// Every frame's coefficients must be computable: the corrector would otherwise pass the frame
// through uncorrected, which is never what the user meant.
void check_coefficients(const std::vector<FrameTiming>& timing, fw::TimeConstants tau,
                        const CorrectOptions& o, const fs::path& csv) {
  for (std::size_t i = 0; i < timing.size(); ++i) {
    fw::CorrectorCoefficients c;
    const fw::CoefficientStatus status =
        i == 0 ? fw::compute_gain_only(tau, timing[i].exposure_ns, c)
               : fw::compute_coefficients(tau, timing[i].exposure_ns, timing[i - 1].readout_ns, c);
    if (status == fw::CoefficientStatus::ok) continue;
    std::ostringstream what;
    what << csv.string() << ": frame " << i << ": no usable coefficients ("
         << fw::to_string(status) << ") for exposure " << seconds_text(timing[i].exposure_s)
         << " s (" << (timing[i].exposure_from_flag ? "--exposure" : "field exposure_s")
         << ") with --tau-h " << seconds_text(o.tau_h_s) << " --tau-c " << seconds_text(o.tau_c_s);
    if (status == fw::CoefficientStatus::gain_out_of_range)
      what << ": exposure / tau_h must be at least ~0.004 (gain 1/(1-exp(-t_e/tau_h)) below 256)";
    throw Error(what.str());
  }
}

bool is_recording_folder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  return fs::exists(dir / "recording.json", ec) || fs::is_empty(dir, ec);
}

void check_output(const CorrectOptions& o) {
  std::error_code ec;
  if (o.output.empty()) fail("OUT: empty path");
  const fs::path parent = fs::absolute(o.output).parent_path();
  if (!fs::is_directory(parent, ec))
    fail(o.output.string(), ": parent folder ", parent.string(), " does not exist");
  if (fs::exists(o.output, ec)) {
    if (fs::equivalent(o.output, o.input, ec))
      fail(o.output.string(), ": OUT is the input recording; write the corrected one elsewhere");
    if (!o.overwrite)
      fail(o.output.string(), ": already exists (use --overwrite to replace it)");
    if (!is_recording_folder(o.output))
      fail(o.output.string(),
           ": exists and is not a recording folder (no recording.json); refusing to replace it");
  }
  if (o.stats) {
    const fs::path stats_parent = fs::absolute(*o.stats).parent_path();
    if (!fs::is_directory(stats_parent, ec))
      fail("--stats ", o.stats->string(), ": folder ", stats_parent.string(), " does not exist");
    if (fs::exists(*o.stats, ec)) {
      if (fs::is_directory(*o.stats, ec)) fail("--stats ", o.stats->string(), ": is a folder");
      if (!o.overwrite)
        fail("--stats ", o.stats->string(), ": already exists (use --overwrite to replace it)");
    }
  }
}

std::string read_whole_file(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) fail(file.string(), ": not a regular file");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string(), ": cannot read");
  std::ostringstream contents;
  contents << in.rdbuf();
  if (!in && !in.eof()) fail(file.string(), ": read error");
  return contents.str();
}

struct FrameStat {
  std::uint64_t frame = 0;
  fw::CarryOver carry_over = fw::CarryOver::first_frame;
  fw::CoefficientStatus coefficient_status = fw::CoefficientStatus::ok;
  double gain = 1.0, carry = 0.0;
  std::uint64_t saturated_low = 0, saturated_high = 0;
  std::uint32_t bad_pixels_replaced = 0;
};

std::string stats_csv(const std::vector<FrameStat>& stats) {
  std::ostringstream csv;
  csv << "frame,carry_over,coefficient_status,gain,carry,saturated_low,saturated_high,"
         "bad_pixels_replaced\n";
  csv << std::setprecision(17);
  for (const FrameStat& s : stats)
    csv << s.frame << ',' << fw::to_string(s.carry_over) << ','
        << fw::to_string(s.coefficient_status) << ',' << s.gain << ',' << s.carry << ','
        << s.saturated_low << ',' << s.saturated_high << ',' << s.bad_pixels_replaced << '\n';
  return csv.str();
}

rec::RecordingInfo corrected_info(const rec::RecordingInfo& input, const CorrectOptions& o) {
  rec::RecordingInfo info = input;
  std::ostringstream source, notes;
  source << "bolo correct of " << o.input.string();
  if (!input.source.empty()) source << " (source: " << input.source << ")";
  notes << "two-frame ghosting correction (Zhang, Brink, Willis, Eq. 6) with tau_h = "
        << seconds_text(o.tau_h_s) << " s, tau_c = " << seconds_text(o.tau_c_s) << " s";
  if (o.exposure_s) notes << ", exposure " << seconds_text(*o.exposure_s) << " s where frames.csv has none";
  if (o.readout_s) notes << ", readout " << seconds_text(*o.readout_s) << " s where frames.csv has none";
  if (o.bad_pixels) notes << ", bad pixels replaced";
  notes << (o.float_output ? "; float32 output of the double-precision reference"
                           : "; uint16 output of the fixed-point firmware pipeline");
  if (!input.notes.empty()) notes << ". Original notes: " << input.notes;
  info.source = source.str();
  info.notes = notes.str();
  nlohmann::json record = {{"tool", "bolo correct"},
                           {"version", BOLO_VERSION},
                           {"input", o.input.string()},
                           {"tau_h_s", o.tau_h_s},
                           {"tau_c_s", o.tau_c_s},
                           {"float", o.float_output},
                           {"bad_pixels", o.bad_pixels}};
  record["exposure_s"] = o.exposure_s ? nlohmann::json(*o.exposure_s) : nlohmann::json(nullptr);
  record["readout_s"] = o.readout_s ? nlohmann::json(*o.readout_s) : nlohmann::json(nullptr);
  info.extra["correction"] = record;
  return info;
}

void print_summary(std::ostream& out, const CorrectOptions& o, const std::vector<FrameStat>& stats,
                   const std::vector<FrameTiming>& timing, std::uint64_t reference_disagreements,
                   bool bad_pixels, std::uint64_t bad_replaced, std::uint64_t bad_unrepairable,
                   double seconds) {
  std::uint64_t by_reason[fw::kCarryOverReasons] = {};
  std::uint64_t low = 0, high = 0, exposure_flag = 0, readout_flag = 0;
  for (const FrameStat& s : stats) {
    ++by_reason[static_cast<std::size_t>(s.carry_over)];
    low += s.saturated_low;
    high += s.saturated_high;
  }
  for (const FrameTiming& t : timing) {
    exposure_flag += t.exposure_from_flag;
    readout_flag += t.readout_from_flag;
  }
  const std::uint64_t n = stats.size();
  const std::uint64_t applied = by_reason[static_cast<std::size_t>(fw::CarryOver::applied)];
  const auto line = [&out](const char* key) -> std::ostream& {
    return out << "  " << std::left << std::setw(14) << key;
  };
  out << "corrected " << o.input.string() << " -> " << o.output.string() << " ("
      << (o.float_output ? "float32, reference" : "uint16, firmware pipeline") << ")\n";
  line("tau") << "tau_h " << seconds_text(o.tau_h_s) << " s, tau_c " << seconds_text(o.tau_c_s) << " s\n";
  line("exposure") << "frames.csv for " << n - exposure_flag << " frames, --exposure for " << exposure_flag << '\n';
  line("readout") << "frames.csv for " << n - readout_flag << " frames, --readout for " << readout_flag << '\n';
  line("frames") << n << ": " << applied << " corrected against the previous frame, " << n - applied
                 << " without (gain only)\n";
  if (n > applied) {
    line("not applied");
    bool first = true;
    for (std::size_t r = 0; r < fw::kCarryOverReasons; ++r) {
      if (r == static_cast<std::size_t>(fw::CarryOver::applied) || by_reason[r] == 0) continue;
      out << (first ? "" : ", ") << fw::to_string(static_cast<fw::CarryOver>(r)) << ' ' << by_reason[r];
      first = false;
    }
    out << '\n';
  }
  if (reference_disagreements > 0)
    line("note") << reference_disagreements
                 << " frames where the float reference judged the predecessor differently\n";
  line("saturated") << low << " pixels low (0), " << high << " high (65535)\n";
  if (bad_pixels) line("bad pixels") << bad_replaced << " replaced, " << bad_unrepairable << " unrepairable\n";
  line("time") << std::fixed << std::setprecision(3) << seconds << " s ("
               << std::setprecision(0) << (seconds > 0 ? static_cast<double>(n) / seconds : 0.0)
               << " fps)\n"
               << std::defaultfloat;
  if (o.stats) line("stats") << o.stats->string() << '\n';
}

}  // namespace

int run_correct(const CorrectOptions& options, std::ostream& out) {
  CorrectOptions o = options;
  if (!o.output.empty() && !o.output.has_filename()) o.output = o.output.parent_path();  // "out/"
  // 1. Flags.
  const fw::TimeConstants tau{flag_ns("--tau-h", o.tau_h_s), flag_ns("--tau-c", o.tau_c_s)};
  Defaults exposure, readout;
  if (o.exposure_s) exposure = {o.exposure_s, flag_ns("--exposure", *o.exposure_s)};
  if (o.readout_s) readout = {o.readout_s, flag_ns("--readout", *o.readout_s)};
  std::uint32_t nominal_period_ns = 0;
  if (o.nominal_fps) {
    if (!std::isfinite(*o.nominal_fps) || !(*o.nominal_fps > 0.25) || *o.nominal_fps > 1e6)
      fail("--nominal-fps ", seconds_text(*o.nominal_fps), ": must be a frame rate between 0.25 and 1e6");
    nominal_period_ns = static_cast<std::uint32_t>(std::lround(1e9 / *o.nominal_fps));
  }
  // 2. Files.
  require_recording_folder(o.input);
  check_output(o);
  hal::RecordingPlayer player(o.input);  // opens and validates the whole recording
  const rec::Recording& recording = player.recording();
  const fs::path csv = o.input / "frames.csv";
  const std::uint32_t width = recording.width(), height = recording.height();
  if (recording.frame_count() == 0) fail(csv.string(), ": no frames");
  // 3. Timing and coefficients of every frame.
  const std::vector<FrameTiming> timing = resolve_timing(recording, csv, exposure, readout);
  check_coefficients(timing, tau, o, csv);

  // 4. The pipeline.
  fw::PipelineConfig config;
  config.corrector.width = width;
  config.corrector.height = height;
  config.corrector.tau = tau;
  config.corrector.default_exposure_ns = exposure.ns;
  config.corrector.default_readout_ns = readout.ns;
  config.corrector.nominal_frame_period_ns = nominal_period_ns;
  config.use_bad_pixels = o.bad_pixels;
  const std::uint32_t bits = recording.info().bits;
  config.bad_pixels.stuck_high =
      static_cast<fw::Pixel>(bits >= 16 || bits == 0 ? 0xFFFFu : (1u << bits) - 1u);
  config.bad_pixels.width = width;
  config.bad_pixels.height = height;
  std::vector<fw::Pixel> arena(fw::Pipeline::arena_pixels(config));
  std::vector<fw::Pixel> corrected_storage(fw::FrameCollector::storage_pixels(width, height));
  fw::FrameCollector corrected(width, height, corrected_storage);
  fw::Pipeline pipeline(config, arena, corrected);

  // --float: the reference gets the raw frame (after bad-pixel replacement when asked).
  std::vector<fw::Pixel> raw_storage(fw::FrameCollector::storage_pixels(width, height));
  fw::FrameCollector raw(width, height, raw_storage);
  std::vector<fw::Pixel> float_bad_storage;
  std::optional<fw::BadPixelStage> float_bad_pixels;
  std::optional<sim::ReferenceCorrector> reference;
  std::optional<Tee> tee;
  std::vector<double> reference_out;
  std::vector<float> float_frame;
  if (o.float_output) {
    fw::LineSink* reference_input = &raw;
    if (o.bad_pixels) {
      float_bad_storage.resize(fw::BadPixelStage::storage_pixels(width, height));
      float_bad_pixels.emplace(config.bad_pixels, float_bad_storage, raw);
      reference_input = &*float_bad_pixels;
    }
    tee.emplace(pipeline.input(), *reference_input);
    std::optional<double> nominal_period_s;
    if (o.nominal_fps) nominal_period_s = 1.0 / *o.nominal_fps;
    reference.emplace(width, height, o.tau_h_s, o.tau_c_s, o.exposure_s, o.readout_s, nominal_period_s);
    reference_out.resize(std::size_t{width} * height);
    float_frame.resize(reference_out.size());
  }
  fw::LineSink& input = tee ? static_cast<fw::LineSink&>(*tee) : pipeline.input();

  // 5. Run, frame by frame, into the atomic writer.
  rec::RecordingWriter writer(o.output, corrected_info(recording.info(), o),
                              {o.overwrite, o.float_output ? rec::DType::f4 : rec::DType::u2});
  // scene.npy (a simulation's steady-state input) still describes the same frames: copy it along.
  std::optional<rec::Recording> scene_source;
  std::vector<float> scene;
  if (recording.has_scene()) {
    scene_source.emplace(o.input);
    scene.resize(std::size_t{width} * height);
  }
  std::vector<FrameStat> stats;
  stats.reserve(timing.size());
  std::uint64_t disagreements = 0, bad_replaced = 0, bad_unrepairable = 0;
  Progress progress("correct", timing.size(), o.progress);
  const auto start = std::chrono::steady_clock::now();
  for (std::uint64_t i = 0; i < timing.size(); ++i) {
    if (player.stream_frame(input) != hal::StreamStatus::frame)
      fail(o.input.string(), ": frame ", i, ": the player delivered no frame");
    if (!corrected.complete()) fail(o.input.string(), ": frame ", i, ": the pipeline delivered an incomplete frame");
    const rec::FrameRow& row = recording.rows()[i];
    const fw::CorrectorFrameStats& cs = pipeline.corrector().last_frame();
    FrameStat s;
    s.frame = i;
    s.carry_over = cs.carry_over;
    s.coefficient_status = cs.coefficient_status;
    s.gain = std::ldexp(static_cast<double>(cs.coefficients.gain_q24), -int{fw::kCoefficientFractionBits});
    s.carry = std::ldexp(static_cast<double>(cs.coefficients.carry_q24), -int{fw::kCoefficientFractionBits});
    s.saturated_low = cs.saturated_low;
    s.saturated_high = cs.saturated_high;
    if (const fw::BadPixelStage* bad = pipeline.bad_pixels()) {
      s.bad_pixels_replaced = bad->last_frame().replaced;
      bad_replaced += bad->last_frame().replaced;
      bad_unrepairable += bad->last_frame().unrepairable;
    }
    if (reference) {
      if (!raw.complete()) fail(o.input.string(), ": frame ", i, ": incomplete frame for the reference");
      const sim::ReferenceFrameInfo info{row.index, row.t_s, timing[i].exposure_s,
                                         timing[i].readout_s, row.ffc.value_or(false)};
      const bool applied = reference->process(info, raw.pixels(), reference_out);
      if (applied != (s.carry_over == fw::CarryOver::applied)) ++disagreements;
      const double g = 1.0 / (1.0 - std::exp(-timing[i].exposure_s / o.tau_h_s));
      s.gain = g;
      s.carry = applied ? g * std::exp(-timing[i - 1].readout_s / o.tau_c_s) : 0.0;
      s.saturated_low = s.saturated_high = 0;
      for (std::size_t p = 0; p < reference_out.size(); ++p) {
        float_frame[p] = static_cast<float>(reference_out[p]);
        s.saturated_low += reference_out[p] <= 0.0;
        s.saturated_high += reference_out[p] >= 65535.0;
      }
      writer.append(std::span<const float>(float_frame), row);
    } else {
      writer.append(corrected.pixels(), row);
    }
    if (scene_source) {
      scene_source->read_scene(i, scene);
      writer.append_scene(scene);
    }
    stats.push_back(s);
    progress.update(i + 1);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.finish();

  if (recording.camera()) writer.set_camera(*recording.camera());
  if (fs::exists(o.input / "poses.tum")) writer.add_file("poses.tum", read_whole_file(o.input / "poses.tum"));

  // 6. Stats first (atomic), then the recording; if the commit fails, the stats go too.
  if (o.stats) rec::write_file_atomically(*o.stats, stats_csv(stats));
  try {
    writer.commit();
  } catch (...) {
    if (o.stats) {
      std::error_code ec;
      fs::remove(*o.stats, ec);
    }
    throw;
  }
  print_summary(out, o, stats, timing, disagreements, o.bad_pixels, bad_replaced, bad_unrepairable,
                seconds);
  return kExitOk;
}

Command add_correct_command(CLI::App& parent) {
  auto o = std::make_shared<CorrectOptions>();
  auto exposure = std::make_shared<double>(0.0);
  auto readout = std::make_shared<double>(0.0);
  auto nominal_fps = std::make_shared<double>(0.0);
  auto stats = std::make_shared<std::string>();
  CLI::App* app = add_command(
      parent, "correct", "Correct the ghosting of a recording (two-frame corrector, firmware pipeline)",
      "Corrects the ghosting of a recording with the two-frame corrector (paper Eq. 6):\n"
      "  I'_i = (I_i - a * I_{i-1}) * g,  a = exp(-t_r,i-1 / tau_c),  g = 1 / (1 - exp(-t_e,i / tau_h))\n"
      "run through the fixed-point firmware pipeline, and write the corrected recording to OUT\n"
      "(uint16 frames.npy; frames.csv, camera.json, poses.tum, scene.npy copied; recording.json\n"
      "notes the correction). Per-frame exposure_s/readout_s from frames.csv win over\n"
      "--exposure/--readout; every frame needs both from one or the other. A frame is corrected\n"
      "against its predecessor unless it is the first, follows an FFC event, a frame drop or a\n"
      "time gap (> 1.5 frame periods); the summary counts the reasons.\n\n"
      "Example (a real recording without timing columns):\n"
      "  bolo correct ../shared/data/real/lepton3-possum out/corrected --tau-h 0.012 --tau-c 0.012 \\\n"
      "      --exposure 0.01 --readout 0.1 --stats out/stats.csv");
  app->add_option("REC", o->input, "Input recording folder")->required();
  app->add_option("OUT", o->output, "Output recording folder (must not exist unless --overwrite)")
      ->required();
  app->add_option("--tau-h", o->tau_h_s, "Heating time constant tau_h, seconds (e.g. 0.012)")
      ->required();
  app->add_option("--tau-c", o->tau_c_s, "Cooling time constant tau_c, seconds (e.g. 0.012)")
      ->required();
  CLI::Option* exposure_opt = app->add_option(
      "--exposure", *exposure, "Exposure (heating) time t_e, seconds, for frames with an empty exposure_s");
  CLI::Option* readout_opt = app->add_option(
      "--readout", *readout, "Readout (cooling) time t_r, seconds, for frames with an empty readout_s");
  app->add_flag("--float", o->float_output,
                "Write float32 frames.npy computed by the double-precision reference instead");
  app->add_flag("--overwrite", o->overwrite, "Replace OUT (and the --stats file) if they exist");
  app->add_flag("--bad-pixels", o->bad_pixels,
                "Replace stuck pixels (reading the 0 or 2^bits-1 rail) by the mean of their 3x3 neighbours first");
  CLI::Option* stats_opt = app->add_option(
      "--stats", *stats,
      "Write per-frame statistics CSV: frame, carry_over reason, coefficient status, gain, carry\n"
      "coefficient (a*g), saturated low/high pixel counts, bad pixels replaced");
  CLI::Option* fps_opt = app->add_option(
      "--nominal-fps", *nominal_fps,
      "Frame rate for time-gap detection (default: learned from the recent t_s intervals)");
  app->add_flag("--no-progress", [o](std::int64_t) { o->progress = false; },
                "Never draw the progress bar (it is drawn only when stderr is a terminal)");
  return {app, [=](std::ostream& out) {
            if (exposure_opt->count()) o->exposure_s = *exposure;
            if (readout_opt->count()) o->readout_s = *readout;
            if (fps_opt->count()) o->nominal_fps = *nominal_fps;
            if (stats_opt->count()) o->stats = fs::path(*stats);
            return run_correct(*o, out);
          }};
}

}  // namespace bolo::cli
