// bolo info REC [--json]: what a recording holds.

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/commands.hpp"
#include "bolo/errors.hpp"
#include "bolo/frame_stack.hpp"
#include "bolo/registry.hpp"

namespace bolo::cli {
namespace {

namespace fs = std::filesystem;

struct Gap {
  std::uint64_t frame = 0;  // the frame after the gap; the gap is between frame-1 and frame
  double interval_s = 0;
};

struct Range {
  std::uint64_t count = 0;  // frames with a value
  double min = 0, max = 0;
  void add(const std::optional<double>& v) {
    if (!v) return;
    if (count == 0 || *v < min) min = *v;
    if (count == 0 || *v > max) max = *v;
    ++count;
  }
};

struct Facts {
  std::uint64_t frames = 0;
  std::optional<double> median_interval_s;
  std::optional<double> t_first, t_last;
  std::vector<std::uint64_t> ffc_events;
  std::vector<Gap> gaps;
  std::vector<std::uint64_t> duplicates;  // frames identical to their predecessor
  Range t_s, exposure_s, readout_s, fpa_temp_c, housing_temp_c;
  std::uint64_t ffc_known = 0;  // frames with a 0/1 ffc cell
  bool scene = false, camera = false, poses = false;
};

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Facts analyse(FrameStack& stack) {
  Facts f;
  const auto& rows = stack.rows();
  f.frames = rows.size();
  std::vector<double> intervals;
  std::vector<std::uint64_t> interval_frame;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const rec::FrameRow& row = rows[i];
    f.t_s.add(row.t_s);
    f.exposure_s.add(row.exposure_s);
    f.readout_s.add(row.readout_s);
    f.fpa_temp_c.add(row.fpa_temp_c);
    f.housing_temp_c.add(row.housing_temp_c);
    if (row.ffc) {
      ++f.ffc_known;
      if (*row.ffc) f.ffc_events.push_back(i);
    }
    if (row.t_s) {
      if (!f.t_first) f.t_first = row.t_s;
      f.t_last = row.t_s;
    }
    if (i > 0 && row.t_s && rows[i - 1].t_s) {
      intervals.push_back(*row.t_s - *rows[i - 1].t_s);
      interval_frame.push_back(i);
    }
  }
  if (!intervals.empty()) {
    f.median_interval_s = median(intervals);
    for (std::size_t k = 0; k < intervals.size(); ++k)
      if (intervals[k] > 1.5 * *f.median_interval_s) f.gaps.push_back({interval_frame[k], intervals[k]});
  }
  // Duplicates: every frame against its predecessor.
  std::vector<float> previous(stack.pixels()), current(stack.pixels());
  for (std::uint64_t i = 0; i < stack.frames(); ++i) {
    stack.read(i, current);
    if (i > 0 && current == previous) f.duplicates.push_back(i);
    std::swap(previous, current);
  }
  f.scene = fs::exists(stack.dir() / "scene.npy");
  f.camera = stack.has_camera();
  f.poses = fs::exists(stack.dir() / "poses.tum");
  return f;
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::string index_list(const std::vector<std::uint64_t>& indices, std::size_t limit = 20) {
  std::ostringstream s;
  for (std::size_t i = 0; i < indices.size() && i < limit; ++i) s << (i ? ", " : "") << indices[i];
  if (indices.size() > limit) s << ", ... (" << indices.size() - limit << " more)";
  return s.str();
}

std::string column_text(const Range& r, std::uint64_t frames, const char* unit, int digits) {
  if (r.count == 0) return "absent";
  std::string text = r.count == frames ? "all frames" : std::to_string(r.count) + " of " + std::to_string(frames) + " frames";
  text += ", " + fixed(r.min, digits);
  if (r.max != r.min) text += " .. " + fixed(r.max, digits);
  return text + unit;
}

void print_text(const FrameStack& stack, const Facts& f, std::ostream& out) {
  const rec::RecordingInfo& info = stack.info();
  const auto line = [&out](const char* key) -> std::ostream& {
    return out << "  " << std::left << std::setw(16) << key;
  };
  out << stack.dir().string() << '\n';
  line("sensor") << (info.sensor.empty() ? "(unknown)" : info.sensor) << '\n';
  line("size") << info.width << " x " << info.height << ", " << info.bits << " bits, units "
               << rec::to_string(info.units) << ", " << (stack.is_float() ? "float32" : "uint16")
               << " frames\n";
  line("frames") << f.frames << '\n';
  line("fps");
  out << (info.fps ? fixed(*info.fps, 2) + " declared" : std::string("not declared"));
  if (f.median_interval_s && *f.median_interval_s > 0)
    out << ", " << fixed(1.0 / *f.median_interval_s, 2) << " measured (median interval "
        << fixed(*f.median_interval_s * 1e3, 1) << " ms)";
  out << '\n';
  line("duration");
  if (f.t_first && f.t_last)
    out << fixed(*f.t_last - *f.t_first, 3) << " s (t_s " << fixed(*f.t_first, 3) << " .. "
        << fixed(*f.t_last, 3) << ")\n";
  else
    out << "unknown (no t_s)\n";
  line("ffc events");
  if (f.ffc_known == 0)
    out << "unknown (no ffc column)\n";
  else if (f.ffc_events.empty())
    out << "none\n";
  else
    out << f.ffc_events.size() << " (before frame " << index_list(f.ffc_events) << ")\n";
  line("gaps");
  if (!f.median_interval_s) {
    out << "unknown (no t_s)\n";
  } else if (f.gaps.empty()) {
    out << "none (no interval > 1.5 x median)\n";
  } else {
    out << f.gaps.size() << " (interval > 1.5 x median):";
    for (std::size_t i = 0; i < f.gaps.size() && i < 20; ++i)
      out << (i ? "," : "") << " frames " << f.gaps[i].frame - 1 << "->" << f.gaps[i].frame << " ("
          << fixed(f.gaps[i].interval_s * 1e3, 1) << " ms)";
    if (f.gaps.size() > 20) out << ", ... (" << f.gaps.size() - 20 << " more)";
    out << '\n';
  }
  line("duplicates");
  if (f.duplicates.empty())
    out << "none\n";
  else
    out << f.duplicates.size() << " (frames identical to their predecessor: "
        << index_list(f.duplicates) << ")\n";
  line("t_s") << column_text(f.t_s, f.frames, " s", 3) << '\n';
  line("exposure_s") << column_text(f.exposure_s, f.frames, " s", 6)
                     << (f.exposure_s.count < f.frames ? "  (bolo correct needs --exposure)" : "")
                     << '\n';
  line("readout_s") << column_text(f.readout_s, f.frames, " s", 6)
                    << (f.readout_s.count < f.frames ? "  (bolo correct needs --readout)" : "")
                    << '\n';
  line("ffc") << (f.ffc_known == 0 ? std::string("absent")
                                   : f.ffc_known == f.frames
                                         ? std::string("all frames")
                                         : std::to_string(f.ffc_known) + " of " + std::to_string(f.frames) + " frames")
              << '\n';
  line("fpa_temp_c") << column_text(f.fpa_temp_c, f.frames, " C", 2) << '\n';
  line("housing_temp_c") << column_text(f.housing_temp_c, f.frames, " C", 2) << '\n';
  line("files") << "scene.npy " << (f.scene ? "yes" : "no") << ", camera.json "
                << (f.camera ? "yes" : "no") << ", poses.tum " << (f.poses ? "yes" : "no") << '\n';
  if (!info.source.empty()) line("source") << info.source << '\n';
  if (!info.notes.empty()) line("notes") << info.notes << '\n';
}

nlohmann::json range_json(const Range& r) {
  nlohmann::json j = {{"frames", r.count}};
  if (r.count > 0) {
    j["min"] = r.min;
    j["max"] = r.max;
  }
  return j;
}

void print_json(const FrameStack& stack, const Facts& f, std::ostream& out) {
  const rec::RecordingInfo& info = stack.info();
  nlohmann::json j;
  j["path"] = stack.dir().string();
  j["sensor"] = info.sensor;
  j["width"] = info.width;
  j["height"] = info.height;
  j["bits"] = info.bits;
  j["units"] = rec::to_string(info.units);
  j["dtype"] = stack.is_float() ? "float32" : "uint16";
  j["frames"] = f.frames;
  j["fps_declared"] = info.fps ? nlohmann::json(*info.fps) : nlohmann::json(nullptr);
  j["median_interval_s"] = f.median_interval_s ? nlohmann::json(*f.median_interval_s) : nlohmann::json(nullptr);
  j["fps_measured"] = f.median_interval_s && *f.median_interval_s > 0
                          ? nlohmann::json(1.0 / *f.median_interval_s)
                          : nlohmann::json(nullptr);
  j["duration_s"] = f.t_first && f.t_last ? nlohmann::json(*f.t_last - *f.t_first) : nlohmann::json(nullptr);
  j["ffc_known"] = f.ffc_known > 0;
  j["ffc_events"] = f.ffc_events;
  nlohmann::json gaps = nlohmann::json::array();
  for (const Gap& g : f.gaps)
    gaps.push_back({{"previous", g.frame - 1}, {"frame", g.frame}, {"interval_s", g.interval_s}});
  j["gaps"] = gaps;
  j["duplicates"] = f.duplicates;
  j["columns"] = {{"t_s", range_json(f.t_s)},
                  {"exposure_s", range_json(f.exposure_s)},
                  {"readout_s", range_json(f.readout_s)},
                  {"ffc", {{"frames", f.ffc_known}}},
                  {"fpa_temp_c", range_json(f.fpa_temp_c)},
                  {"housing_temp_c", range_json(f.housing_temp_c)}};
  j["files"] = {{"scene.npy", f.scene}, {"camera.json", f.camera}, {"poses.tum", f.poses}};
  j["source"] = info.source;
  j["notes"] = info.notes;
  out << j.dump(2) << '\n';
}

}  // namespace

int run_info(const InfoOptions& options, std::ostream& out) {
  FrameStack stack(options.input);
  const Facts facts = analyse(stack);
  if (options.json)
    print_json(stack, facts, out);
  else
    print_text(stack, facts, out);
  return kExitOk;
}

Command add_info_command(CLI::App& parent) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* app = add_command(
      parent, "info", "Describe a recording: size, frames, fps, FFC events, gaps, duplicates, timing columns",
      "Prints what a recording holds: sensor, size, bits, units, frame count, declared and measured fps\n"
      "(median t_s interval), duration, FFC events, gaps (intervals > 1.5 x median), duplicate\n"
      "frames, which timing columns are filled, temperature ranges, optional files.");
  app->add_option("REC", options->input, "Recording folder (recording.json, frames.npy, frames.csv)")
      ->required();
  app->add_flag("--json", options->json, "Print the same facts as one JSON object");
  return {app, [options](std::ostream& out) { return run_info(*options, out); }};
}

}  // namespace bolo::cli
