#pragma once
// Reading and writing the shared recording format (docs: ../shared/docs/recording-format.md).
// Host code: errors are thrown as bolo::rec::Error whose message names the file and, where it
// applies, the frame and the field, e.g.
//   "rec/frames.csv: frame 12: field t_s: not monotonic (0.9 after 1.0)".

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/recording/atomic_folder.hpp"

namespace bolo::rec {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Units { counts, centikelvin, counts8 };
std::string to_string(Units units);

// recording.json
struct RecordingInfo {
  std::string sensor;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t bits = 16;
  std::optional<double> fps;
  Units units = Units::counts;
  std::string source;
  std::string notes;
  nlohmann::json extra = nlohmann::json::object();  // unknown keys, kept when a tool rewrites
};

// One row of frames.csv. Empty cells are std::nullopt.
struct FrameRow {
  std::uint64_t index = 0;
  std::optional<double> t_s;
  std::optional<double> exposure_s;
  std::optional<double> readout_s;
  std::optional<bool> ffc;
  std::optional<double> fpa_temp_c;
  std::optional<double> housing_temp_c;
};

RecordingInfo read_recording_json(const std::filesystem::path& file);
void write_recording_json(const std::filesystem::path& file, const RecordingInfo& info);

// Validates: header, column names and order, index == row number, finite numbers,
// strictly increasing t_s, non-negative exposure/readout, ffc in {0,1,empty}.
std::vector<FrameRow> read_frames_csv(const std::filesystem::path& file);
void write_frames_csv(const std::filesystem::path& file, std::span<const FrameRow> rows);
// frames.csv one row at a time (a recording of any length in constant memory); finish() closes it.
// Each row is validated as write_frames_csv validates it (index = row number, t_s increasing).
class FramesCsvWriter {
 public:
  // `shown_as` names the file in messages (the destination, when `file` is in a temporary folder).
  explicit FramesCsvWriter(const std::filesystem::path& file, std::filesystem::path shown_as = {});
  ~FramesCsvWriter();
  FramesCsvWriter(const FramesCsvWriter&) = delete;
  FramesCsvWriter& operator=(const FramesCsvWriter&) = delete;
  // Throws Error naming the file, frame and field if `row` cannot be the next row; writes nothing.
  void check(const FrameRow& row) const;
  void append(const FrameRow& row);
  void finish();
  std::uint64_t rows() const { return rows_; }

 private:
  std::filesystem::path path_, shown_as_;
  std::ofstream out_;
  std::uint64_t rows_ = 0;
  std::optional<double> last_t_;
  bool finished_ = false;
};

enum class DType { u2, f4 };

struct NpyHeader {
  DType dtype = DType::u2;
  std::vector<std::uint64_t> shape;
  std::uint64_t data_offset = 0;  // byte offset of the array data in the file
};

// Parses and validates a .npy header (versions 1.0, 2.0, 3.0; little-endian; C order) and checks
// that the file is long enough for the data it declares.
NpyHeader read_npy_header(const std::filesystem::path& file);

// A whole float32 array of any shape as .npy bytes (version 1.0), e.g. a map for truth/.
std::string encode_npy_f4(const std::vector<std::uint64_t>& shape, std::span<const float> values);

// Random access to the frames of a (N, H, W) .npy stack without loading all of it.
class NpyFrameReader {
 public:
  NpyFrameReader(const std::filesystem::path& file, DType expected);
  const NpyHeader& header() const { return header_; }
  std::uint64_t frames() const { return header_.shape[0]; }
  std::uint64_t height() const { return header_.shape[1]; }
  std::uint64_t width() const { return header_.shape[2]; }
  void read_frame(std::uint64_t index, std::span<std::uint16_t> out);  // u2 files
  void read_frame(std::uint64_t index, std::span<float> out);          // f4 files
  // One row of one frame; lets a line source stream without a frame buffer.
  void read_row(std::uint64_t frame, std::uint64_t row, std::span<std::uint16_t> out);

 private:
  std::filesystem::path path_;
  NpyHeader header_;
  std::ifstream in_;
};

// Appends (H, W) frames to a (N, H, W) .npy stack; the shape is patched in by finish().
class NpyStackWriter {
 public:
  NpyStackWriter(const std::filesystem::path& file, DType dtype, std::uint64_t height,
                 std::uint64_t width);
  void append(std::span<const std::uint16_t> frame);
  void append(std::span<const float> frame);
  void finish();  // writes the final shape; the writer is unusable afterwards
  std::uint64_t frames() const { return frames_; }

 private:
  std::filesystem::path path_;
  DType dtype_;
  std::uint64_t height_, width_, frames_ = 0;
  std::ofstream out_;
  bool finished_ = false;
};

// A whole recording folder, validated on open: recording.json, frames.npy (uint16, shape agreeing
// with recording.json), frames.csv (one row per frame); scene.npy (float32, same shape) if present.
class Recording {
 public:
  explicit Recording(const std::filesystem::path& dir);
  const std::filesystem::path& dir() const { return dir_; }
  const RecordingInfo& info() const { return info_; }
  const std::vector<FrameRow>& rows() const { return rows_; }
  std::uint64_t frame_count() const { return rows_.size(); }
  std::uint32_t width() const { return info_.width; }
  std::uint32_t height() const { return info_.height; }
  void read_frame(std::uint64_t index, std::span<std::uint16_t> out) { frames_.read_frame(index, out); }
  void read_row(std::uint64_t frame, std::uint64_t row, std::span<std::uint16_t> out) {
    frames_.read_row(frame, row, out);
  }
  bool has_scene() const { return scene_.has_value(); }
  void read_scene(std::uint64_t index, std::span<float> out);
  // camera.json as written, if present (validated to be a JSON object).
  const std::optional<nlohmann::json>& camera() const { return camera_; }

 private:
  std::filesystem::path dir_;
  RecordingInfo info_;
  std::vector<FrameRow> rows_;
  NpyFrameReader frames_;
  std::optional<NpyFrameReader> scene_;
  std::optional<nlohmann::json> camera_;
};

// Writes a recording through an AtomicFolder, renamed into place on commit(), so a reader never
// sees a half-written recording. An existing destination is an error unless `overwrite`, and
// only a recording (or an empty folder) is replaced.
class RecordingWriter {
 public:
  struct Options {
    bool overwrite = false;
    DType frames_dtype = DType::u2;  // f4 for float output (e.g. `bolo correct --float`)
  };
  RecordingWriter(std::filesystem::path dir, RecordingInfo info, Options options);
  RecordingWriter(std::filesystem::path dir, RecordingInfo info)
      : RecordingWriter(std::move(dir), std::move(info), Options{}) {}
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  void append(std::span<const std::uint16_t> frame, const FrameRow& row);
  void append(std::span<const float> frame, const FrameRow& row);
  // scene.npy (float32, the steady-state input of a simulation): one per appended frame.
  void append_scene(std::span<const float> scene);
  void set_camera(const nlohmann::json& camera);
  // Any further file in the recording (poses.tum, truth/...), written at commit. Relative path.
  void add_file(const std::filesystem::path& relative, std::string contents);
  void commit();
  std::uint64_t frames() const { return rows_.rows(); }

 private:
  std::filesystem::path dir_;
  AtomicFolder folder_;
  RecordingInfo info_;
  Options options_;
  NpyStackWriter frames_;
  std::optional<NpyStackWriter> scene_;
  FramesCsvWriter rows_;
  std::optional<nlohmann::json> camera_;
  std::vector<std::pair<std::filesystem::path, std::string>> extra_files_;
};

#if BOLO_RECORDING_HAS_PNG  // libpng found at configure time (board builds may go without)
// A folder of 16-bit grayscale PNG frames (sorted by file name) read as a recording without
// metadata: times come from `fps`. Throws Error naming the file on a non-16-bit or mismatched PNG.
struct PngFolder {
  std::vector<std::filesystem::path> files;
  std::uint32_t width = 0, height = 0;
};
PngFolder scan_png_folder(const std::filesystem::path& dir);
void read_png16(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                std::span<std::uint16_t> out);
void write_png16(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                 std::span<const std::uint16_t> pixels);
// 8-bit RGB, for rendered views.
void write_png_rgb8(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                    std::span<const std::uint8_t> rgb);
#endif

// Writes `contents` to `file` via a temporary sibling and rename.
void write_file_atomically(const std::filesystem::path& file, const std::string& contents);

}  // namespace bolo::rec
