#pragma once
// The output side of a correction: refusals before anything is written, the corrected
// recording's recording.json, the --stats file.

#include <filesystem>
#include <string>
#include <vector>

#include "bolo/correct/correct_recording.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::correct {

// OUT (and --stats) may be written: parent folders exist, nothing is replaced unless
// --overwrite, and never the input recording `recording` (empty for a live source) or something
// that is not a recording.
void check_output(const CorrectRequest& request, const std::filesystem::path& recording);

// The input's recording.json with the correction noted (source, notes, extra.correction); `live`:
// the input was a live source (`input` is what it says of itself), not a recording.
rec::RecordingInfo corrected_info(const rec::RecordingInfo& input, const CorrectRequest& request, bool live);

// The --stats CSV: one row per frame.
std::string stats_csv(const std::vector<FrameStats>& stats);

std::string read_whole_file(const std::filesystem::path& file);

}  // namespace bolo::correct
