#include "bolo/correct/correction_summary.hpp"

#include <iomanip>

namespace bolo::correct {

void SummaryTally::on_frame(const FrameStats& s) {
  ++frames;
  ++by_reason[static_cast<std::size_t>(s.carry_over)];
  saturated_low += s.saturated_low;
  saturated_high += s.saturated_high;
  exposure_from_flag += s.exposure_from_flag;
  readout_from_flag += s.readout_from_flag;
  reference_disagreements += s.reference_disagrees;
  bad_replaced += s.bad_pixels_replaced;
  bad_unrepairable += s.bad_pixels_unrepairable;
}

void print_summary(std::ostream& out, const CorrectRequest& request, const SummaryTally& t,
                   const CorrectResult& result) {
  CorrectRequest o = request;
  if (!o.output.empty() && !o.output.has_filename()) o.output = o.output.parent_path();  // "out/"
  const std::uint64_t n = t.frames;
  const std::uint64_t applied = t.by_reason[static_cast<std::size_t>(fw::CarryOver::applied)];
  const auto line = [&out](const char* key) -> std::ostream& {
    return out << "  " << std::left << std::setw(14) << key;
  };
  out << "corrected " << o.input.string() << " -> " << o.output.string() << " ("
      << (o.float_output ? "float32, reference" : "uint16, firmware pipeline") << ")\n";
  line("tau") << "tau_h " << seconds_text(o.tau_h_s) << " s, tau_c " << seconds_text(o.tau_c_s) << " s\n";
  if (result.live)
    line("input") << "live source: " << result.skipped << " faulted frames skipped; device faults: " << result.faults
                  << '\n';
  const char* timing = result.live ? "the source for " : "frames.csv for ";
  line("exposure") << timing << n - t.exposure_from_flag << " frames, --exposure for " << t.exposure_from_flag << '\n';
  line("readout") << timing << n - t.readout_from_flag << " frames, --readout for " << t.readout_from_flag << '\n';
  line("frames") << n << ": " << applied << " corrected against the previous frame, " << n - applied
                 << " without (gain only)\n";
  if (n > applied) {
    line("not applied");
    bool first = true;
    for (std::size_t r = 0; r < fw::kCarryOverReasons; ++r) {
      if (r == static_cast<std::size_t>(fw::CarryOver::applied) || t.by_reason[r] == 0) continue;
      out << (first ? "" : ", ") << fw::to_string(static_cast<fw::CarryOver>(r)) << ' ' << t.by_reason[r];
      first = false;
    }
    out << '\n';
  }
  if (t.reference_disagreements > 0)
    line("note") << t.reference_disagreements
                 << " frames where the float reference judged the predecessor differently\n";
  line("saturated") << t.saturated_low << " pixels low (0), " << t.saturated_high << " high (65535)\n";
  if (o.bad_pixels) line("bad pixels") << t.bad_replaced << " replaced, " << t.bad_unrepairable << " unrepairable\n";
  const double seconds = result.seconds;
  line("time") << std::fixed << std::setprecision(3) << seconds << " s ("
               << std::setprecision(0) << (seconds > 0 ? static_cast<double>(n) / seconds : 0.0)
               << " fps)\n"
               << std::defaultfloat;
  if (o.stats) line("stats") << o.stats->string() << '\n';
}

}  // namespace bolo::correct
