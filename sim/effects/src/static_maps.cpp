// Static maps added to the reading: offset_fpn (per pixel), column_fpn and row_fpn (readout
// stripes), and shading (the smooth radial field from lens and housing). Diagnose fits each on
// the time-averaged residual, split into columns, rows, a radial field and the rest.

#include <cmath>

#include "bolo/effects/stats.hpp"
#include "entries.hpp"
#include "fixed_pattern.hpp"
#include "map_statistics.hpp"

namespace bolo::effects {
namespace {

struct OffsetFpnSchema {
  static constexpr std::string_view id = "offset_fpn";
  static constexpr Param sigma{"sigma", "counts", 5.0, 0.0, 1e4};
};

struct ColumnFpnSchema {
  static constexpr std::string_view id = "column_fpn";
  static constexpr Param sigma{"sigma", "counts", 5.0, 0.0, 1e4};
};

struct RowFpnSchema {
  static constexpr std::string_view id = "row_fpn";
  static constexpr Param sigma{"sigma", "counts", 5.0, 0.0, 1e4};
};

struct ShadingSchema {
  static constexpr std::string_view id = "shading";
  static constexpr Param amplitude{"amplitude", "counts", 30.0, -1e4, 1e4};  // at the corners
};

}  // namespace
}  // namespace bolo::effects

namespace bolo::sim {
namespace {

// y += amplitude * (xn^2 + yn^2) / 2, xn and yn in [-1, 1]: amplitude at the corners, 0 at the
// centre. Not reset by shutter events (it comes from in front of the shutter).
class ShadingEffect final : public Effect {
  using S = effects::ShadingSchema;

 public:
  ShadingEffect(const EffectSpec& spec, const SimulationInfo& info) : w_(info.width), h_(info.height) {
    effects::Params p(spec);
    amplitude_ = p.number(S::amplitude);
    p.finish();
  }
  const char* id() const override { return S::id.data(); }
  void on_reading(const FrameState&, std::span<double> y) override {
    for (std::uint32_t r = 0; r < h_; ++r)
      for (std::uint32_t c = 0; c < w_; ++c) y[std::size_t{r} * w_ + c] += field(r, c);
  }
  nlohmann::json parameters() const override { return {{S::amplitude.name, amplitude_}}; }
  std::vector<std::pair<std::string, std::vector<float>>> maps() const override {
    std::vector<float> m(std::size_t{w_} * h_);
    for (std::uint32_t r = 0; r < h_; ++r)
      for (std::uint32_t c = 0; c < w_; ++c) m[std::size_t{r} * w_ + c] = static_cast<float>(field(r, c));
    return {{"shading_field", m}};
  }

 private:
  double field(std::uint32_t r, std::uint32_t c) const {
    const double xn = w_ > 1 ? 2.0 * c / (w_ - 1) - 1.0 : 0.0;
    const double yn = h_ > 1 ? 2.0 * r / (h_ - 1) - 1.0 : 0.0;
    return amplitude_ * (xn * xn + yn * yn) / 2.0;
  }
  std::uint32_t w_, h_;
  double amplitude_;
};

}  // namespace
}  // namespace bolo::sim

namespace bolo::diag {
namespace {

class StaticMapFit final : public FittedEffect {
 public:
  StaticMapFit(std::vector<float> map, nlohmann::json params, std::string sim, Where where)
      : map_(std::move(map)), params_(std::move(params)), sim_(std::move(sim)), where_(std::move(where)) {}
  void predict(int, std::span<float> out) const override { std::copy(map_.begin(), map_.end(), out.begin()); }
  nlohmann::json params() const override { return params_; }
  std::string simulator_effect() const override { return sim_; }
  Where where() const override { return where_; }

 private:
  std::vector<float> map_;
  nlohmann::json params_;
  std::string sim_;
  Where where_;
};

// The time-averaged residual split into columns, rows, a smooth radial field and the rest;
// each static-map effect takes its own part.
enum class StaticPart { offset, column, row, shading };

template <StaticPart part_>
class StaticMapCandidate final : public Candidate {
 public:
  bool needs_distant_holdout() const override { return true; }
  const char* id() const override {
    switch (part_) {
      case StaticPart::offset: return effects::OffsetFpnSchema::id.data();
      case StaticPart::column: return effects::ColumnFpnSchema::id.data();
      case StaticPart::row: return effects::RowFpnSchema::id.data();
      case StaticPart::shading: return effects::ShadingSchema::id.data();
    }
    return "";
  }
  int parameter_count() const override { return 1; }
  void prepare(const DiagnoseData& d, const std::vector<float>& r) override { data_ = &d; residual_ = &r; }
  std::unique_ptr<FittedEffect> fit(const std::vector<char>& train) const override {
    const DiagnoseData& d = *data_;
    // A static background already holds every static pattern: nothing to fit.
    if (!d.has_scene) return nullptr;
    const int H = d.shape.height, W = d.shape.width;
    const std::size_t P = d.shape.pixels();
    const PixelSums s = pixel_sums(d, *residual_, train, part_ == StaticPart::offset ? &d.baseline : nullptr);
    TimeAveraged avg = time_averaged(d, s);
    std::vector<double>&mean = avg.mean, &noise = avg.noise, &col = avg.col, &row = avg.row;
    std::vector<double> noise_col(W, 1.57 * avg.typical_noise / H), noise_row(H, 1.57 * avg.typical_noise / W);
    // The radial field of the simulator's shading, (x_n^2 + y_n^2)/2 with x_n, y_n in [-1, 1].
    std::vector<double> field(P);
    double fm = 0;
    for (int rr = 0; rr < H; ++rr)
      for (int c = 0; c < W; ++c) {
        const double xn = 2.0 * c / std::max(1, W - 1) - 1, yn = 2.0 * rr / std::max(1, H - 1) - 1;
        field[rr * W + c] = 0.5 * (xn * xn + yn * yn);
        fm += field[rr * W + c];
      }
    fm /= double(P);
    double ff = 0, fr = 0;
    for (std::size_t p = 0; p < P; ++p) {
      const double f = field[p] - fm, rest = mean[p];
      ff += f * f;
      fr += f * rest;
    }
    const double amplitude = ff > 0 ? fr / ff : 0.0;
    const bool stripes_in_columns = avg.stripes_in_columns, stripes_in_rows = avg.stripes_in_rows;
    if (part_ == StaticPart::column && !stripes_in_columns) return nullptr;
    if (part_ == StaticPart::row && !stripes_in_rows) return nullptr;
    std::vector<float> map(P, 0.0f);
    nlohmann::json params;
    std::string sim;
    Where where;
    switch (part_) {
      case StaticPart::column: {
        shrink(col, noise_col);
        for (std::size_t p = 0; p < P; ++p) map[p] = float(col[p % W]);
        params = {{effects::ColumnFpnSchema::sigma.name, rms(col)}};
        sim = effects::SpecText(effects::ColumnFpnSchema::id).set(effects::ColumnFpnSchema::sigma, number(rms(col))).str();
        where = whole(d, "stripes: column means of the time-averaged residual");
        int worst = int(std::max_element(col.begin(), col.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); }) - col.begin());
        where.summary += " (strongest column " + std::to_string(worst) + ")";
        break;
      }
      case StaticPart::row: {
        shrink(row, noise_row);
        for (std::size_t p = 0; p < P; ++p) map[p] = float(row[p / W]);
        params = {{effects::RowFpnSchema::sigma.name, rms(row)}};
        sim = effects::SpecText(effects::RowFpnSchema::id).set(effects::RowFpnSchema::sigma, number(rms(row))).str();
        where = whole(d, "stripes: row means of the time-averaged residual");
        break;
      }
      case StaticPart::shading: {
        // Noise of a one-parameter fit: residual variance over the pixel-frames times 1/sum f^2.
        const double a = amplitude;
        for (std::size_t p = 0; p < P; ++p) map[p] = float(a * (field[p] - fm));
        params = {{effects::ShadingSchema::amplitude.name, a}};
        sim = effects::SpecText(effects::ShadingSchema::id).set(effects::ShadingSchema::amplitude, number(a)).str();
        where = whole(d, "smooth radial field of the time-averaged residual (centre to corners)");
        break;
      }
      case StaticPart::offset: {
        // What column and row stripes leave (they are effects of their own). The radial shading
        // field splits into a column and a row part, so shading competes with both and wins
        // with its single parameter when the pattern is radial.
        std::vector<double> rest = avg.pixel_pattern(), noise_rest = noise;
        // A pattern whose spread follows the level is gain_fpn's (its static part); where both
        // are there, this takes the offset's share of each pixel.
        const std::vector<double> level2 = squared_levels(s);
        const LevelSplit split = split_by_level(rest, noise_rest, level2);
        if (!split.has_offset) return nullptr;
        if (split.has_gain)
          for (std::size_t p = 0; p < P; ++p) rest[p] *= split.offset_share(level2[p], noise_rest[p]);
        else
          shrink(rest, noise_rest);
        for (std::size_t p = 0; p < P; ++p) map[p] = float(rest[p]);
        // Beside a gain pattern the map holds each pixel's expected offset share (shrunk); the
        // spread is the variance component's.
        const double sigma = split.has_gain ? std::sqrt(split.offset_var) : rms(rest);
        params = {{effects::OffsetFpnSchema::sigma.name, sigma}};
        sim = effects::SpecText(effects::OffsetFpnSchema::id).set(effects::OffsetFpnSchema::sigma, number(sigma)).str();
        where = whole(d, "static pixel-to-pixel pattern in the time-averaged residual");
        break;
      }
    }
    return std::make_unique<StaticMapFit>(std::move(map), params, sim, where);
  }

 private:
  const DiagnoseData* data_ = nullptr;
  const std::vector<float>* residual_ = nullptr;
};

// Per-pixel slope of the residual against a regressor image (no intercept):
// gain_fpn against the level, tau_spread against d(baseline)/d(ln tau).

}  // namespace
}  // namespace bolo::diag

namespace bolo::effects {

EffectEntry offset_fpn() {
  using S = OffsetFpnSchema;
  return make_entry<sim::FixedPatternEffect<S, sim::Pattern::offset>, diag::StaticMapCandidate<diag::StaticPart::offset>>(
      S::id, {S::sigma});
}

EffectEntry column_fpn() {
  using S = ColumnFpnSchema;
  return make_entry<sim::FixedPatternEffect<S, sim::Pattern::column>, diag::StaticMapCandidate<diag::StaticPart::column>>(
      S::id, {S::sigma});
}

EffectEntry row_fpn() {
  using S = RowFpnSchema;
  return make_entry<sim::FixedPatternEffect<S, sim::Pattern::row>, diag::StaticMapCandidate<diag::StaticPart::row>>(
      S::id, {S::sigma});
}

EffectEntry shading() {
  using S = ShadingSchema;
  return make_entry<sim::ShadingEffect, diag::StaticMapCandidate<diag::StaticPart::shading>>(S::id, {S::amplitude});
}

}  // namespace bolo::effects
