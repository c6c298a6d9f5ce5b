#pragma once
// What a command's input spec names, for a command that runs over a whole sequence (odometry): a
// recording folder (a folder, or the source spec file:REC), or another source (a camera, a
// transfer log) read whole into memory, its faulted frames skipped and counted.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "bolo/odometry/run_odometry.hpp"

namespace bolo::cli {

// The recording folder `spec` names, or nothing for another source. Throws bolo::cli::Error
// naming the spec for an unknown or malformed one or a camera that streams on without
// `frames_given`, and naming the folder when a recording's does not exist or is not a folder.
std::optional<std::filesystem::path> recording_folder_or_live(const std::string& spec, bool frames_given);

// A live source's frames, up to max_frames or its end. Throws bolo::cli::Error naming the spec
// when it cannot be opened, gives up after more than max_faults faults in a row, or delivers none.
odo::LiveFrames read_live_frames(const std::string& spec, std::optional<std::uint64_t> max_frames,
                                 std::uint64_t max_faults);

}  // namespace bolo::cli
