// report.html (report.hpp): what the baseline missed, where, what explains it, and the fit before
// and after, with the noise floor beside every number.

#include "bolo/diagnose/report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "bolo/recording/recording.hpp"
#include "svg.hpp"

namespace bolo::diag {
namespace {

// Time-averaged residual over valid pixel-frames.
std::vector<double> mean_map(const DiagnoseData& d, const std::vector<float>& r) {
  const std::size_t P = d.shape.pixels();
  std::vector<double> sum(P, 0), cnt(P, 0);
  for (int n = 0; n < d.shape.n; ++n) {
    const float* f = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    for (std::size_t p = 0; p < P; ++p)
      if (v[p]) { sum[p] += f[p]; cnt[p] += 1; }
  }
  for (std::size_t p = 0; p < P; ++p) sum[p] = cnt[p] > 0 ? sum[p] / cnt[p] : 0.0;
  return sum;
}

// Diverging colour map (blue - white - red) of `values` over +-range, as a base64 PNG <img>.
std::string png_image(const std::vector<double>& values, int width, int height, double range,
                      const std::filesystem::path& scratch, const std::string& name) {
  const int scale = width < 200 ? 3 : (width < 400 ? 2 : 1);
  const int W = width * scale, H = height * scale;
  std::vector<std::uint8_t> rgb(std::size_t(W) * H * 3);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double v = std::clamp(values[std::size_t(y / scale) * width + x / scale] / range, -1.0, 1.0);
      std::uint8_t* px = &rgb[(std::size_t(y) * W + x) * 3];
      const auto fade = static_cast<std::uint8_t>(255 * (1 - std::fabs(v)));
      px[0] = v > 0 ? 255 : fade;
      px[1] = fade;
      px[2] = v < 0 ? 255 : fade;
    }
  const std::filesystem::path file = scratch / (".report-" + name + ".png");
  rec::write_png_rgb8(file, W, H, rgb);
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::filesystem::remove(file);
  return "<img alt='" + name + "' src='data:image/png;base64," + base64(bytes) + "'>";
}

std::vector<double> frame_rms(const DiagnoseData& d, const std::vector<float>& r) {
  const std::size_t P = d.shape.pixels();
  std::vector<double> out(d.shape.n, NAN);
  for (int n = 0; n < d.shape.n; ++n) {
    const float* f = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    double s = 0, c = 0;
    for (std::size_t p = 0; p < P; ++p)
      if (v[p]) { s += double(f[p]) * f[p]; c += 1; }
    if (c > 0) out[n] = std::sqrt(s / c);
  }
  return out;
}

std::vector<double> frame_mean(const DiagnoseData& d, const std::vector<float>& r) {
  const std::size_t P = d.shape.pixels();
  std::vector<double> out(d.shape.n, NAN);
  for (int n = 0; n < d.shape.n; ++n) {
    const float* f = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    double s = 0, c = 0;
    for (std::size_t p = 0; p < P; ++p)
      if (v[p]) { s += f[p]; c += 1; }
    if (c > 0) out[n] = s / c;
  }
  return out;
}

// Removes the median (a global offset would hide the pattern) and returns the 99th percentile
// of what is left, the display range.
double centre_for_display(std::vector<double>& values) {
  std::vector<double> tmp = values;
  std::nth_element(tmp.begin(), tmp.begin() + tmp.size() / 2, tmp.end());
  const double median = tmp[tmp.size() / 2];
  for (double& v : values) v -= median;
  for (std::size_t i = 0; i < values.size(); ++i) tmp[i] = std::fabs(values[i]);
  std::nth_element(tmp.begin(), tmp.begin() + tmp.size() * 99 / 100, tmp.end());
  return std::max(1e-6, tmp[tmp.size() * 99 / 100]);
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

std::string fmt_delta_bic(double v) { return v >= kExactEvidence ? "exact" : fmt(v); }

std::string where_text(const Where& w) {
  std::ostringstream s;
  s << html_escape(w.summary) << "<br><small>frames ";
  for (std::size_t i = 0; i < w.frames.size() && i < 8; ++i) s << (i ? ", " : "") << w.frames[i].first << "-" << w.frames[i].second;
  if (w.frames.size() > 8) s << ", ...";
  s << "; rows " << w.row0 << "-" << w.row1 << "; cols " << w.col0 << "-" << w.col1 << "</small>";
  return s.str();
}

std::vector<double> to_vector(const nlohmann::json& j) {
  std::vector<double> v;
  for (const auto& x : j) v.push_back(x.is_number() ? x.get<double>() : NAN);
  return v;
}

}  // namespace

std::string render_report(const Diagnosis& d, const DiagnoseData& data, const ResidualViews& views,
                          const std::filesystem::path& scratch) {
  std::ostringstream h;
  h << "<!DOCTYPE html><html><head><meta charset='utf-8'><title>bolo diagnose: " << html_escape(d.recording)
    << "</title><style>body{font-family:sans-serif;max-width:1000px;margin:1em auto;padding:0 1em}"
       "table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ccc;padding:3px 6px;vertical-align:top}"
       "figure{display:inline-block;margin:6px}figcaption{font-size:12px}code{background:#f3f3f3}</style></head><body>";
  h << "<h1>bolo diagnose: " << html_escape(d.recording) << "</h1>";
  h << "<p>" << data.shape.n << " frames of " << data.shape.width << "x" << data.shape.height << " at " << fmt(data.fps)
    << " fps, units " << html_escape(data.units) << ".</p>";
  h << "<h2>Baseline</h2><p><b>Model:</b> " << html_escape(d.baseline.model) << ". <b>Assumption:</b> "
    << html_escape(d.baseline.assumption) << ".</p><p>Parameters: <code>" << html_escape(d.baseline.to_json()["params"].dump())
    << "</code></p>";
  h << "<table><tr><th>noise floor (temporal differences, static pixels)</th><th>baseline fit RMS</th><th>baseline held-out RMS</th>"
       "<th>held-out RMS with the findings</th></tr><tr><td>"
    << fmt(d.noise_floor_rms) << "</td><td>" << fmt(d.fit_rms) << "</td><td>" << fmt(d.heldout_rms) << "</td><td>"
    << fmt(d.final_heldout_rms) << "</td></tr></table>";

  h << "<h2>Findings</h2>";
  if (d.findings.empty()) {
    h << "<p><b>None.</b> No catalogue effect improves the held-out fit significantly; the baseline explains this "
         "recording down to what the tests can resolve.</p>";
  } else {
    h << "<table><tr><th>#</th><th>effect</th><th>evidence (held-out)</th><th>parameters</th><th>where</th>"
         "<th>held-out RMS before &rarr; after</th></tr>";
    int i = 0;
    for (const Finding& f : d.findings)
      h << "<tr><td>" << ++i << "</td><td><b>" << f.effect << "</b><br><small><code>" << html_escape(f.simulator_effect)
        << "</code></small></td><td>&Delta;BIC " << fmt_delta_bic(f.evidence.delta_bic) << "<br>p " << fmt(f.evidence.p_value)
        << "<br>block z " << fmt(f.evidence.block_z) << "<br>n_eff " << fmt(f.evidence.n_eff) << "</td><td><code>"
        << html_escape(f.params.dump()) << "</code></td><td>" << where_text(f.where) << "</td><td>"
        << fmt(f.heldout_rms_before) << " &rarr; " << fmt(f.heldout_rms_after) << "<br><small>noise floor "
        << fmt(d.noise_floor_rms) << "</small></td></tr>";
    h << "</table>";
  }
  h << "<p>Each effect of the catalogue was fitted on training blocks of frames and scored on the held-out blocks "
       "(contiguous runs of frames, never single frames); a finding needs held-out &Delta;BIC above the threshold with "
       "an effective sample size corrected for spatial and temporal correlation of the residual, and a gain that is "
       "consistent over held-out blocks. Selection is greedy: the strongest finding is removed, the rest are scored again.</p>";

  h << "<h2>Fit before and after</h2>";
  std::vector<double> before_map = mean_map(data, views.before), after_map = mean_map(data, views.after);
  const double range = centre_for_display(before_map);
  centre_for_display(after_map);
  h << "<figure>" << png_image(before_map, data.shape.width, data.shape.height, range, scratch, "mean-before")
    << "<figcaption>time-averaged residual, baseline, spatial median removed (&plusmn;" << fmt(range) << ")</figcaption></figure>";
  h << "<figure>" << png_image(after_map, data.shape.width, data.shape.height, range, scratch, "mean-after")
    << "<figcaption>time-averaged residual, with the findings (same scale)</figcaption></figure>";
  // The frame where the baseline misses most.
  const std::vector<double> rms_before = frame_rms(data, views.before), rms_after = frame_rms(data, views.after);
  int worst = 0;
  for (int n = 0; n < data.shape.n; ++n)
    if (std::isfinite(rms_before[n]) && (!std::isfinite(rms_before[worst]) || rms_before[n] > rms_before[worst])) worst = n;
  const std::size_t P = data.shape.pixels();
  std::vector<double> wb(P), wa(P);
  for (std::size_t p = 0; p < P; ++p) { wb[p] = data.frame(views.before, worst)[p]; wa[p] = data.frame(views.after, worst)[p]; }
  const double frange = std::max(3 * d.noise_floor_rms, centre_for_display(wb));
  centre_for_display(wa);
  h << "<br><figure>" << png_image(wb, data.shape.width, data.shape.height, frange, scratch, "worst-before")
    << "<figcaption>residual of frame " << worst << " (largest RMS), baseline, median removed (&plusmn;" << fmt(frange) << ")</figcaption></figure>";
  h << "<figure>" << png_image(wa, data.shape.width, data.shape.height, frange, scratch, "worst-after")
    << "<figcaption>frame " << worst << " with the findings</figcaption></figure>";
  h << "<br>" << svg_plot("per-frame residual RMS", "frame", {{"baseline", "#c0392b", rms_before}, {"with findings", "#2471a3", rms_after}},
                          d.noise_floor_rms, "noise floor");
  h << "<br>" << svg_plot("per-frame mean residual", "frame",
                          {{"baseline", "#c0392b", frame_mean(data, views.before)}, {"with findings", "#2471a3", frame_mean(data, views.after)}});

  h << "<h2>Where the baseline residual lives</h2>";
  const auto& loc = d.locate;
  h << svg_plot("column profile of the time-averaged residual", "column", {{"baseline", "#c0392b", to_vector(loc["column_profile"])}});
  h << "<br>" << svg_plot("row profile of the time-averaged residual", "row", {{"baseline", "#c0392b", to_vector(loc["row_profile"])}});
  if (loc.contains("spectrum")) {
    Series sp{"power", "#7d3c98", to_vector(loc["spectrum"]["power"])};
    sp.dx = loc["spectrum"]["frequency_hz_step"].get<double>();
    sp.x0 = sp.dx;
    h << "<br>" << svg_plot("temporal spectrum of the frame-mean residual", "Hz", {sp});
  }
  for (const char* key : {"after_shutter_events", "after_input_steps"}) {
    const auto& e = loc[key];
    if (e["events"].empty()) continue;
    Series s{key == std::string("after_shutter_events") ? "frame-mean residual" : "frame RMS residual", "#117a65", to_vector(e["mean"])};
    s.x0 = e["lags"][0].get<int>() * -1.0;
    h << "<br>" << svg_plot(std::string(key == std::string("after_shutter_events") ? "averaged around flagged shutter events"
                                                                                   : "averaged around the largest input steps") +
                                " (frames " + e["events"].dump() + ")",
                            "frames from the event", {s});
  }
  h << "<h3>Correlation of the baseline residual with physical regressors</h3><table><tr><th>regressor</th><th>correlation</th></tr>";
  for (auto& [k, v] : loc["correlations"].items()) h << "<tr><td>" << k << "</td><td>" << fmt(v.get<double>()) << "</td></tr>";
  h << "</table>";

  h << "<h2>Unexplained</h2>";
  if (d.unexplained.empty()) h << "<p>Nothing structured is left above the noise.</p>";
  else {
    h << "<table><tr><th>where</th><th>RMS</th></tr>";
    for (const Unexplained& u : d.unexplained) h << "<tr><td>" << where_text(u.where) << "</td><td>" << fmt(u.rms) << "</td></tr>";
    h << "</table>";
  }
  h << "<h2>Every candidate, every round</h2><table><tr><th>round</th><th>effect</th><th>&Delta;BIC</th><th>block z</th>"
       "<th>held-out SSE ratio</th><th>accepted</th></tr>";
  for (const CandidateScore& s : d.scores)
    h << "<tr><td>" << s.round << "</td><td>" << s.effect << "</td><td>" << fmt_delta_bic(s.evidence.delta_bic) << "</td><td>"
      << fmt(s.evidence.block_z) << "</td><td>"
      << (s.evidence.sse_before > 0 ? fmt(s.evidence.sse_after / s.evidence.sse_before) : "") << "</td><td>"
      << (s.accepted ? "yes" : s.note) << "</td></tr>";
  h << "</table></body></html>\n";
  return h.str();
}

}  // namespace bolo::diag
