// PNG I/O with libpng. libpng reports errors through a callback that must not return; ours
// longjmps back into small "guarded" functions that hold no C++ objects with destructors, and
// the callers turn a failure into an Error naming the file. All libpng state is owned by RAII
// wrappers outside the guarded functions, so nothing leaks on a corrupt file.

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <system_error>

#include <png.h>

#include "bolo/recording/recording.hpp"
#include "detail.hpp"

namespace bolo::rec {
namespace {

using detail::fail;
namespace fs = std::filesystem;

struct PngError {
  char message[256] = "unknown libpng error";
  std::jmp_buf jump;
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* error = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(error->message, sizeof error->message, "%s", message ? message : "unknown error");
  std::longjmp(error->jump, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

struct PngHeader {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
};

// ---- guarded steps: setjmp targets; no objects with non-trivial destructors in these frames.

bool guarded_read_header(png_structp png, png_infop info, PngError& error, FILE* fp, PngHeader& out) {
  if (setjmp(error.jump)) return false;
  png_init_io(png, fp);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  png_get_IHDR(png, info, &out.width, &out.height, &out.bit_depth, &out.color_type, nullptr,
               nullptr, nullptr);
  return true;
}

bool guarded_read_image(png_structp png, png_infop info, PngError& error, png_bytepp rows) {
  if (setjmp(error.jump)) return false;
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  png_read_image(png, rows);
  png_read_end(png, nullptr);
  return true;
}

void write_to_string(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  bool ok = true;
  try {
    out->append(reinterpret_cast<const char*>(data), length);
  } catch (...) {
    ok = false;
  }
  if (!ok) png_error(png, "out of memory");
}

void flush_nothing(png_structp) {}

bool guarded_write(png_structp png, png_infop info, PngError& error, std::string* out,
                   png_uint_32 width, png_uint_32 height, int bit_depth, int color_type,
                   png_bytepp rows) {
  if (setjmp(error.jump)) return false;
  png_set_write_fn(png, out, write_to_string, flush_nothing);
  png_set_IHDR(png, info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

// ---- RAII owners.

struct FileCloser {
  void operator()(FILE* fp) const { std::fclose(fp); }
};

struct ReadStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ReadStructs() = default;
  ReadStructs(const ReadStructs&) = delete;
  ReadStructs& operator=(const ReadStructs&) = delete;
  ~ReadStructs() {
    if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
  }
};

class PngReader {
 public:
  explicit PngReader(const fs::path& file) : file_(file) {
    fp_.reset(std::fopen(file.c_str(), "rb"));
    if (!fp_) fail(file, std::string("cannot open: ") + std::strerror(errno));
    unsigned char signature[8] = {};
    if (std::fread(signature, 1, 8, fp_.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
      fail(file, "not a PNG file (bad signature)");
    s_.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error_, on_png_error, on_png_warning);
    if (!s_.png) fail(file, "cannot initialise libpng");
    s_.info = png_create_info_struct(s_.png);
    if (!s_.info) fail(file, "cannot initialise libpng");
    if (!guarded_read_header(s_.png, s_.info, error_, fp_.get(), header_))
      fail(file, std::string("corrupt PNG: ") + error_.message);
  }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  const PngHeader& header() const { return header_; }

  void require_gray16() const {
    if (header_.bit_depth == 16 && header_.color_type == PNG_COLOR_TYPE_GRAY) return;
    std::string kind;
    switch (header_.color_type) {
      case PNG_COLOR_TYPE_GRAY: kind = "grayscale"; break;
      case PNG_COLOR_TYPE_GRAY_ALPHA: kind = "grayscale+alpha"; break;
      case PNG_COLOR_TYPE_RGB: kind = "RGB"; break;
      case PNG_COLOR_TYPE_RGB_ALPHA: kind = "RGBA"; break;
      case PNG_COLOR_TYPE_PALETTE: kind = "palette"; break;
      default: kind = "color type " + std::to_string(header_.color_type); break;
    }
    fail(file_, std::to_string(header_.bit_depth) + "-bit " + kind +
                    " PNG, expected 16-bit grayscale");
  }

  void read_image(png_bytepp rows) {
    if (!guarded_read_image(s_.png, s_.info, error_, rows))
      fail(file_, std::string("corrupt PNG: ") + error_.message);
  }

 private:
  fs::path file_;
  std::unique_ptr<FILE, FileCloser> fp_;
  PngError error_;
  ReadStructs s_;  // destroyed before fp_ is closed
  PngHeader header_;
};

std::string size_text(std::uint64_t width, std::uint64_t height) {
  return "width " + std::to_string(width) + ", height " + std::to_string(height);
}

void write_png(const fs::path& file, std::uint32_t width, std::uint32_t height, int bit_depth,
               int color_type, std::size_t bytes_per_pixel, const unsigned char* data) {
  std::vector<png_bytep> rows(height);
  const std::size_t stride = std::size_t{width} * bytes_per_pixel;
  for (std::uint32_t y = 0; y < height; ++y)
    rows[y] = const_cast<png_bytep>(data + y * stride);  // libpng does not write through them

  std::string encoded;
  PngError error;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, on_png_error, on_png_warning);
  if (!png) fail(file, "cannot initialise libpng");
  png_infop info = png_create_info_struct(png);
  const bool have_info = info != nullptr;
  const bool ok = have_info && guarded_write(png, info, error, &encoded, width, height, bit_depth,
                                             color_type, rows.data());
  png_destroy_write_struct(&png, have_info ? &info : nullptr);  // nulls both pointers
  if (!have_info) fail(file, "cannot initialise libpng");
  if (!ok) fail(file, std::string("cannot encode PNG: ") + error.message);
  write_file_atomically(file, encoded);
}

void check_size(const fs::path& file, std::uint32_t width, std::uint32_t height,
                std::size_t values, std::size_t per_pixel) {
  if (width == 0 || height == 0) fail(file, "empty image (" + size_text(width, height) + ")");
  const std::uint64_t expected = std::uint64_t{width} * height * per_pixel;
  if (values != expected)
    fail(file, "buffer holds " + std::to_string(values) + " values, expected " +
                   std::to_string(expected) + " (" + size_text(width, height) + ")");
}

bool has_png_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png";
}

}  // namespace

PngFolder scan_png_folder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) fail(dir, "not a folder");
  PngFolder folder;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& path = it->path();
    if (has_png_extension(path) && !path.filename().string().starts_with(".") &&
        it->is_regular_file())
      folder.files.push_back(path);
  }
  if (ec) fail(dir, "cannot list the folder: " + ec.message());
  if (folder.files.empty()) fail(dir, "no *.png files");
  std::sort(folder.files.begin(), folder.files.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  for (std::size_t i = 0; i < folder.files.size(); ++i) {
    const PngReader reader(folder.files[i]);
    reader.require_gray16();
    const PngHeader& h = reader.header();
    if (i == 0) {
      folder.width = h.width;
      folder.height = h.height;
    } else if (h.width != folder.width || h.height != folder.height) {
      fail(folder.files[i], size_text(h.width, h.height) + ", but " +
                                folder.files[0].filename().string() + " has " +
                                size_text(folder.width, folder.height));
    }
  }
  return folder;
}

void read_png16(const fs::path& file, std::uint32_t width, std::uint32_t height,
                std::span<std::uint16_t> out) {
  check_size(file, width, height, out.size(), 1);
  PngReader reader(file);
  reader.require_gray16();
  if (reader.header().width != width || reader.header().height != height)
    fail(file, size_text(reader.header().width, reader.header().height) + ", expected " +
                   size_text(width, height));
  auto* bytes = reinterpret_cast<unsigned char*>(out.data());
  std::vector<png_bytep> rows(height);
  for (std::uint32_t y = 0; y < height; ++y) rows[y] = bytes + std::size_t{y} * width * 2;
  reader.read_image(rows.data());
  // PNG samples are big-endian; convert in place to host order.
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = static_cast<std::uint16_t>((bytes[2 * i] << 8) | bytes[2 * i + 1]);
}

void write_png16(const fs::path& file, std::uint32_t width, std::uint32_t height,
                 std::span<const std::uint16_t> pixels) {
  check_size(file, width, height, pixels.size(), 1);
  std::vector<unsigned char> big_endian(pixels.size() * 2);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    big_endian[2 * i] = static_cast<unsigned char>(pixels[i] >> 8);
    big_endian[2 * i + 1] = static_cast<unsigned char>(pixels[i] & 0xff);
  }
  write_png(file, width, height, 16, PNG_COLOR_TYPE_GRAY, 2, big_endian.data());
}

void write_png_rgb8(const fs::path& file, std::uint32_t width, std::uint32_t height,
                    std::span<const std::uint8_t> rgb) {
  check_size(file, width, height, rgb.size(), 3);
  write_png(file, width, height, 8, PNG_COLOR_TYPE_RGB, 3, rgb.data());
}

}  // namespace bolo::rec
