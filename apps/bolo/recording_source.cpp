#include "bolo/recording_source.hpp"

#include "bolo/errors.hpp"
#include "bolo/frame_stack.hpp"
#include "bolo/hal/source_registry.hpp"

namespace bolo::cli {

std::filesystem::path recording_folder(const std::filesystem::path& input, const char* command) {
  hal::SourceSpec spec;
  try {
    spec = hal::parse_source_spec(input.string());
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
  if (spec.backend.scheme != "file")
    fail(input.string(), ": bolo ", command, " takes a recording (a folder or file:REC); record ",
         spec.backend.scheme, " with `bolo capture` first");
  require_recording_folder(spec.argument);
  return spec.argument;
}

}  // namespace bolo::cli
