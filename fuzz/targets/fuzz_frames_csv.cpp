// frames.csv: read_frames_csv on the input as a file. Properties: what is accepted is valid
// (index == row number, finite values, strictly increasing t_s, non-negative exposure/readout),
// and write_frames_csv writes it back to a file that reads back to the same rows.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <vector>

#include "bolo/recording/recording.hpp"
#include "fuzz_support.hpp"

namespace {

using namespace bolo;

bool same(const std::optional<double>& a, const std::optional<double>& b) {
  if (a.has_value() != b.has_value()) return false;
  return !a || std::memcmp(&*a, &*b, sizeof(double)) == 0;  // bit for bit (keeps -0)
}

bool same(const rec::FrameRow& a, const rec::FrameRow& b) {
  return a.index == b.index && same(a.t_s, b.t_s) && same(a.exposure_s, b.exposure_s) &&
         same(a.readout_s, b.readout_s) && a.ffc == b.ffc && same(a.fpa_temp_c, b.fpa_temp_c) &&
         same(a.housing_temp_c, b.housing_temp_c);
}

void check_valid(const std::vector<rec::FrameRow>& rows) {
  std::optional<double> last_t;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const rec::FrameRow& r = rows[i];
    BOLO_FUZZ_CHECK(r.index == i);
    for (const auto* v : {&r.t_s, &r.exposure_s, &r.readout_s, &r.fpa_temp_c, &r.housing_temp_c})
      BOLO_FUZZ_CHECK(!*v || std::isfinite(**v));
    BOLO_FUZZ_CHECK(!r.exposure_s || *r.exposure_s >= 0);
    BOLO_FUZZ_CHECK(!r.readout_s || *r.readout_s >= 0);
    if (r.t_s) {
      BOLO_FUZZ_CHECK(!last_t || *r.t_s > *last_t);
      last_t = r.t_s;
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path file = fuzz::scratch_dir() / "frames.csv";
  fuzz::write_file(file, std::span(data, size));
  std::vector<rec::FrameRow> rows;
  try {
    rows = rec::read_frames_csv(file);
  } catch (const rec::Error&) {
    return 0;
  }
  check_valid(rows);
  const std::filesystem::path copy = fuzz::scratch_dir() / "frames-copy.csv";
  try {
    rec::write_frames_csv(copy, rows);
    const std::vector<rec::FrameRow> again = rec::read_frames_csv(copy);
    BOLO_FUZZ_CHECK(again.size() == rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) BOLO_FUZZ_CHECK(same(rows[i], again[i]));
  } catch (const rec::Error& e) {
    std::fprintf(stderr, "accepted rows did not round-trip: %s\n", e.what());
    BOLO_FUZZ_CHECK(!"rows read from frames.csv were refused when written and read back");
  }
  return 0;
}
