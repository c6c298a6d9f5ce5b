#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "bolo/recording/recording.hpp"
#include "detail.hpp"

namespace bolo::rec {

void write_file_atomically(const std::filesystem::path& file, const std::string& contents) {
  const std::filesystem::path tmp = detail::temp_sibling(file, "tmp");
  std::error_code ec;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) detail::fail(file, std::string("cannot create: ") + std::strerror(errno));
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.close();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      detail::fail(file, "write failed");
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    detail::fail(file, "cannot rename the temporary file into place: " + ec.message());
  }
}

}  // namespace bolo::rec
