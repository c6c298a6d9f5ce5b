// frames.csv: one row per frame, strictly validated.

#include <cerrno>
#include <charconv>
#include <cstring>
#include <string_view>

#include "bolo/recording/recording.hpp"
#include "detail.hpp"

namespace bolo::rec {
namespace {

using detail::fail;
using detail::fail_frame;

constexpr std::string_view kHeader = "index,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c";
constexpr std::size_t kColumns = 7;
constexpr std::string_view kColumnNames[kColumns] = {
    "index", "t_s", "exposure_s", "readout_s", "ffc", "fpa_temp_c", "housing_temp_c"};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Shown in messages; long or binary junk is cut short.
std::string quoted(std::string_view cell, std::size_t max = 40) {
  std::string text;
  for (char c : cell.substr(0, max)) text += (static_cast<unsigned char>(c) < 0x20) ? '?' : c;
  if (cell.size() > max) text += "...";
  return "'" + text + "'";
}

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      cells.push_back(trim(line.substr(start)));
      return cells;
    }
    cells.push_back(trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

struct CellParser {
  const std::filesystem::path& file;
  std::uint64_t frame;

  std::uint64_t index(std::string_view cell) const {
    if (cell.empty()) fail_frame(file, frame, "index", "empty (the index is required)");
    std::uint64_t value = 0;
    const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
    if (ec != std::errc() || ptr != cell.data() + cell.size())
      fail_frame(file, frame, "index", "not a non-negative integer: " + quoted(cell));
    return value;
  }

  std::optional<double> number(std::string_view cell, std::string_view field) const {
    if (cell.empty()) return std::nullopt;
    double value = 0;
    const auto [ptr, ec] =
        std::from_chars(cell.data(), cell.data() + cell.size(), value, std::chars_format::general);
    if (ec == std::errc::result_out_of_range)
      fail_frame(file, frame, field, "out of range: " + quoted(cell));
    if (ec != std::errc() || ptr != cell.data() + cell.size())
      fail_frame(file, frame, field, "not a number: " + quoted(cell));
    return value;
  }

  std::optional<bool> ffc(std::string_view cell) const {
    if (cell.empty()) return std::nullopt;
    if (cell == "0") return false;
    if (cell == "1") return true;
    fail_frame(file, frame, "ffc", quoted(cell) + ", expected 0, 1 or empty");
  }
};

void append_number(std::string& out, const std::optional<double>& value) {
  if (value) out += detail::format_double(*value);
}

}  // namespace

std::vector<FrameRow> read_frames_csv(const std::filesystem::path& file) {
  const std::string text = detail::read_text_file(file);
  std::string_view rest = text;
  if (rest.starts_with("\xEF\xBB\xBF")) rest.remove_prefix(3);  // UTF-8 byte-order mark

  // Lines end in "\n" or "\r\n" (Python's csv module writes the latter).
  std::vector<std::string_view> lines;
  while (!rest.empty()) {
    const std::size_t nl = rest.find('\n');
    std::string_view line = rest.substr(0, nl);
    if (line.ends_with('\r')) line.remove_suffix(1);
    lines.push_back(line);
    if (nl == std::string_view::npos) break;
    rest.remove_prefix(nl + 1);
  }
  while (!lines.empty() && trim(lines.back()).empty()) lines.pop_back();  // blank lines at the end
  if (lines.empty()) fail(file, "empty file (expected the header line '" + std::string(kHeader) + "')");

  std::string header;
  for (std::string_view name : split_cells(lines[0])) header += std::string(name) + ",";
  header.pop_back();
  if (header != kHeader) {
    const std::size_t columns = split_cells(lines[0]).size();
    fail(file, "header: expected '" + std::string(kHeader) + "', got " + quoted(lines[0], 120) +
                   (columns != kColumns ? " (" + std::to_string(columns) + " columns)" : ""));
  }

  std::vector<FrameRow> rows;
  rows.reserve(lines.size() - 1);
  detail::RowValidator validator(file);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::uint64_t frame = i - 1;
    const CellParser parse{file, frame};
    if (trim(lines[i]).empty()) fail_frame(file, frame, {}, "empty line");
    const std::vector<std::string_view> cells = split_cells(lines[i]);
    if (cells.size() != kColumns)
      fail_frame(file, frame, {}, std::to_string(cells.size()) + " columns, expected " +
                                      std::to_string(kColumns) + " (" + std::string(kHeader) + ")");
    FrameRow row;
    row.index = parse.index(cells[0]);
    row.t_s = parse.number(cells[1], kColumnNames[1]);
    row.exposure_s = parse.number(cells[2], kColumnNames[2]);
    row.readout_s = parse.number(cells[3], kColumnNames[3]);
    row.ffc = parse.ffc(cells[4]);
    row.fpa_temp_c = parse.number(cells[5], kColumnNames[5]);
    row.housing_temp_c = parse.number(cells[6], kColumnNames[6]);
    validator.check(row, frame, cells[1]);
    rows.push_back(row);
  }
  return rows;
}

namespace {

void append_row(std::string& text, const FrameRow& row) {
  text += std::to_string(row.index);
  text += ',';
  append_number(text, row.t_s);
  text += ',';
  append_number(text, row.exposure_s);
  text += ',';
  append_number(text, row.readout_s);
  text += ',';
  if (row.ffc) text += *row.ffc ? '1' : '0';
  text += ',';
  append_number(text, row.fpa_temp_c);
  text += ',';
  append_number(text, row.housing_temp_c);
  text += '\n';
}

// The validator as it stands after `rows` rows whose last time stamp was `last_t`.
detail::RowValidator validator_after(const std::filesystem::path& file, const std::optional<double>& last_t) {
  detail::RowValidator validator(file);
  if (last_t) validator.seed(*last_t);
  return validator;
}

}  // namespace

void write_frames_csv(const std::filesystem::path& file, std::span<const FrameRow> rows) {
  detail::RowValidator validator(file);
  std::string text(kHeader);
  text += '\n';
  for (std::size_t i = 0; i < rows.size(); ++i) {
    validator.check(rows[i], i);
    append_row(text, rows[i]);
  }
  write_file_atomically(file, text);
}

FramesCsvWriter::FramesCsvWriter(const std::filesystem::path& file, std::filesystem::path shown_as)
    : path_(file), shown_as_(shown_as.empty() ? file : std::move(shown_as)) {
  out_.open(file, std::ios::binary | std::ios::trunc);
  if (!out_) fail(shown_as_, std::string("cannot create: ") + std::strerror(errno));
  out_ << kHeader << '\n';
  if (!out_) fail(shown_as_, "write failed");
}

FramesCsvWriter::~FramesCsvWriter() = default;

void FramesCsvWriter::check(const FrameRow& row) const {
  if (finished_) fail(shown_as_, "append after finish()");
  validator_after(shown_as_, last_t_).check(row, rows_);
}

void FramesCsvWriter::append(const FrameRow& row) {
  check(row);
  std::string text;
  append_row(text, row);
  out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out_) fail_frame(shown_as_, rows_, {}, "write failed");
  if (row.t_s) last_t_ = row.t_s;
  ++rows_;
}

void FramesCsvWriter::finish() {
  if (finished_) fail(shown_as_, "finish() called twice");
  finished_ = true;
  out_.close();
  if (!out_) fail(shown_as_, "write failed while finishing");
}

}  // namespace bolo::rec
