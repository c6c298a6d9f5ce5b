#include "bolo/recording_source.hpp"

#include "bolo/errors.hpp"
#include "bolo/frame_stack.hpp"
#include "bolo/hal/source_registry.hpp"

namespace bolo::cli {

std::filesystem::path recording_folder(const std::filesystem::path& input, const char* command) {
  try {
    return hal::recording_folder_of(input.string(), command);
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
}

}  // namespace bolo::cli
