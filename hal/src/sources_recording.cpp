// file:REC (and a bare path): a recording in the shared format, through the recording player.

#include "bolo/hal/recording_player.hpp"
#include "builtin_sources.hpp"

namespace bolo::hal::detail {

void add_recording_sources(std::vector<SourceBackend>& backends) {
  SourceBackend file;
  file.scheme = "file";
  file.argument = "REC";
  file.argument_help = "a recording folder, e.g. file:rec";
  file.summary = "a recording in the shared format (the recording player)";
  file.finite = true;
  file.open = [](const std::string& path, const SourceOptions&) {
    auto player = std::make_unique<RecordingPlayer>(path);
    std::string sensor = player->recording().info().sensor;
    return std::make_unique<OpenedSource>(std::move(player), std::move(sensor));
  };
  backends.push_back(std::move(file));
}

}  // namespace bolo::hal::detail
