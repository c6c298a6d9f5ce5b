#include "corrected_output.hpp"

#include <fstream>
#include <iomanip>
#include <sstream>

#include "bolo/correct/fail.hpp"

namespace bolo::correct {
namespace fs = std::filesystem;
namespace {

bool is_recording_folder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  return fs::exists(dir / "recording.json", ec) || fs::is_empty(dir, ec);
}

}  // namespace

void check_output(const CorrectRequest& o, const fs::path& recording) {
  std::error_code ec;
  if (o.output.empty()) fail("OUT: empty path");
  const fs::path parent = fs::absolute(o.output).parent_path();
  if (!fs::is_directory(parent, ec))
    fail(o.output.string(), ": parent folder ", parent.string(), " does not exist");
  if (fs::exists(o.output, ec)) {
    if (fs::equivalent(o.output, recording, ec))
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

rec::RecordingInfo corrected_info(const rec::RecordingInfo& input, const CorrectRequest& o, bool live) {
  rec::RecordingInfo info = input;
  std::ostringstream source, notes;
  source << o.tool << " of " << (live ? "live source " : "") << o.input.string();
  if (!input.source.empty()) source << " (source: " << input.source << ")";
  notes << "two-frame ghosting correction (Zhang, Brink, Willis, Eq. 6) with tau_h = "
        << seconds_text(o.tau_h_s) << " s, tau_c = " << seconds_text(o.tau_c_s) << " s";
  const char* timing = live ? "the source gives none" : "frames.csv has none";
  if (o.exposure_s) notes << ", exposure " << seconds_text(*o.exposure_s) << " s where " << timing;
  if (o.readout_s) notes << ", readout " << seconds_text(*o.readout_s) << " s where " << timing;
  if (o.nuc) notes << ", NUC (gain, offset) from " << o.nuc->string();
  if (o.bad_pixels) notes << ", bad pixels replaced";
  notes << (o.float_output ? "; float32 output of the double-precision reference"
                           : "; uint16 output of the fixed-point firmware pipeline");
  if (!input.notes.empty()) notes << ". Original notes: " << input.notes;
  info.source = source.str();
  info.notes = notes.str();
  nlohmann::json record = {{"tool", o.tool},
                           {"version", BOLO_VERSION},
                           {"input", o.input.string()},
                           {"tau_h_s", o.tau_h_s},
                           {"tau_c_s", o.tau_c_s},
                           {"float", o.float_output},
                           {"bad_pixels", o.bad_pixels}};
  record["exposure_s"] = o.exposure_s ? nlohmann::json(*o.exposure_s) : nlohmann::json(nullptr);
  record["readout_s"] = o.readout_s ? nlohmann::json(*o.readout_s) : nlohmann::json(nullptr);
  if (o.nuc) record["nuc"] = o.nuc->string();
  if (live) record["live"] = true;
  info.extra["correction"] = record;
  return info;
}

std::string stats_csv(const std::vector<FrameStats>& stats) {
  std::ostringstream csv;
  csv << "frame,carry_over,coefficient_status,gain,carry,saturated_low,saturated_high,"
         "bad_pixels_replaced\n";
  csv << std::setprecision(17);
  for (const FrameStats& s : stats)
    csv << s.frame << ',' << fw::to_string(s.carry_over) << ','
        << fw::to_string(s.coefficient_status) << ',' << s.gain << ',' << s.carry << ','
        << s.saturated_low << ',' << s.saturated_high << ',' << s.bad_pixels_replaced << '\n';
  return csv.str();
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

}  // namespace bolo::correct
