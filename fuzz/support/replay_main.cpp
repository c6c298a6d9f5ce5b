// Runs a fuzz target's LLVMFuzzerTestOneInput once over each given file, or each file in a given
// folder (sorted by name; README* skipped), without libFuzzer: any compiler, any build type.
// This is how the test suite replays fuzz/corpus/<target> and fuzz/regressions/<target>. A crash
// or a broken property aborts; an exception other than the target's expected refusals escapes
// and terminates. A folder that does not exist counts as empty (a target without regressions).
//
//   fuzz_<target>_replay PATH...

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

void run_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "replay: cannot read %s\n", file.c_str());
    std::exit(2);
  }
  const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  // An exactly sized copy, so a read past the end of the input is caught by ASan.
  std::unique_ptr<std::uint8_t[]> exact(new std::uint8_t[bytes.size() + (bytes.empty() ? 1 : 0)]);
  std::copy(bytes.begin(), bytes.end(), exact.get());
  std::fprintf(stderr, "replay: %s (%zu bytes)\n", file.c_str(), bytes.size());
  LLVMFuzzerTestOneInput(exact.get(), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FILE|FOLDER...\n", argv[0]);
    return 2;
  }
  std::size_t total = 0;
  for (int i = 1; i < argc; ++i) {
    const fs::path path = argv[i];
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
      std::vector<fs::path> files;
      for (const auto& entry : fs::directory_iterator(path))
        if (entry.is_regular_file() && !entry.path().filename().string().starts_with("README"))
          files.push_back(entry.path());
      std::sort(files.begin(), files.end());
      for (const fs::path& file : files) run_file(file);
      std::printf("replay: %zu inputs from %s\n", files.size(), path.c_str());
      total += files.size();
    } else if (fs::exists(path, ec)) {
      run_file(path);
      ++total;
    } else {
      std::printf("replay: %s does not exist: 0 inputs\n", path.c_str());
    }
  }
  std::printf("replay: %zu inputs, no crash\n", total);
  return 0;
}
