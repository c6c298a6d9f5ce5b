#pragma once
// The recording folder a command's input names: a folder, or the source spec file:REC. Commands
// that need a recording's files (odometry) refuse other sources by name.

#include <filesystem>

namespace bolo::cli {

// Throws bolo::cli::Error naming the spec for a source that is not a recording, and naming the
// folder when it does not exist or is not a folder.
std::filesystem::path recording_folder(const std::filesystem::path& input, const char* command);

}  // namespace bolo::cli
