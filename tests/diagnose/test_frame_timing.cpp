// The baseline follows every frame's timing (frames.csv's exposure and readout, the interval
// where the readout is missing): a recording whose timing wanders by a fraction of a percent is
// a null, not a global offset fluctuation of several noise sigmas.

#include <fstream>
#include <set>
#include <sstream>

#include <catch2/catch.hpp>

#include "diagnose_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

// frames.csv with `column` (0-based) of every data row replaced by `value`.
void set_frames_csv_column(const fs::path& rec, int column, const std::string& value, int only_row = -1) {
  edit_frames_csv(rec / "frames.csv", rec / "frames.csv", [&](int row, std::vector<std::string>& cells) {
    if (only_row < 0 || only_row == row) cells[column] = value;
  });
}

void check_null(const nlohmann::json& d) {
  INFO(d.dump(1).substr(0, 4000));
  CHECK(d["findings"].empty());
  // The baseline explains it down to the noise: held-out RMS within 5 % of the noise floor.
  CHECK(d["baseline"]["heldout_rms"].get<double>() < 1.05 * d["noise_floor_rms"].get<double>());
  CHECK(unexplained_with(d, "global offset fluctuation") == 0);
}

}  // namespace

TEST_CASE("exposure and readout jittered frame to frame (0.5 %, logged exactly): a null", "[diagnose][null][timing]") {
  TempDir tmp;
  const fs::path rec = simulate(tmp, "jitter", {}, 31, {"--timing-jitter", "0.005"});
  // The simulator wrote a different exposure for (nearly) every frame.
  const rec::Recording recording(rec);
  std::set<double> exposures;
  for (const auto& row : recording.rows()) exposures.insert(row.exposure_s.value());
  CHECK(exposures.size() > 100);
  // ... and the interval to the next frame is that frame's exposure plus its readout.
  const auto& rows = recording.rows();
  for (std::size_t n = 0; n + 1 < rows.size(); ++n)
    REQUIRE(*rows[n + 1].t_s - *rows[n].t_s == Approx(*rows[n].exposure_s + *rows[n].readout_s).margin(1e-12));
  const nlohmann::json d = diagnose(rec, tmp / "jitter.d");
  check_null(d);
  CHECK(d["baseline"]["params"]["tau_h_fitted"] == true);
  CHECK(d["baseline"]["params"]["tau_c_s"].get<double>() == Approx(0.012).epsilon(0.05));
  CHECK(d["baseline"]["params"]["tau_h_s"].get<double>() == Approx(0.012).epsilon(0.1));

  SECTION("readouts left empty: each is the interval to the next frame less the exposure") {
    set_frames_csv_column(rec, 3, "");
    check_null(diagnose(rec, tmp / "no-readout.d"));
  }
}

TEST_CASE("frames.csv timing the baseline cannot use is refused, naming frame and field", "[diagnose][timing]") {
  TempDir tmp;
  const fs::path rec = simulate(tmp, "zero", {}, 32, {"--frames", "20"});
  set_frames_csv_column(rec, 2, "0", 7);
  const CliResult r = run_bolo({"diagnose", rec.string(), "--out", (tmp / "zero.d").string(), "--no-progress"});
  CHECK(r.code != 0);
  CHECK(contains(r.err, "frames.csv"));
  CHECK(contains(r.err, "frame 7"));
  CHECK(contains(r.err, "exposure_s"));
}

TEST_CASE("simulate refuses a timing jitter outside 0..0.1", "[diagnose][timing]") {
  TempDir tmp;
  for (const char* jitter : {"0.5", "-0.01"}) {
    const CliResult r = run_bolo({"simulate", (tmp / "j").string(), "--frames", "2", "--timing-jitter", jitter});
    CHECK(r.code != 0);
    CHECK(contains(r.err, "--timing-jitter: must be 0..0.1"));
    CHECK(!fs::exists(tmp / "j"));
  }
}
