// bolo render REC OUT.png: PNG views of a recording (one frame, a contact sheet, side by side
// with a second recording), with one display range for every frame unless --agc.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <memory>
#include <sstream>
#include <tuple>
#include <vector>

#include "bolo/commands.hpp"
#include "bolo/errors.hpp"
#include "bolo/frame_stack.hpp"
#include "bolo/image.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/registry.hpp"

namespace bolo::cli {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kRangeSampleBudget = std::size_t{1} << 22;  // pixels read for the range
constexpr std::uint64_t kMaxCanvasPixels = 100'000'000;

// "A:B" -> two finite numbers; errors name the flag.
std::pair<double, double> parse_pair(const char* flag, const std::string& text, const char* form) {
  const std::size_t colon = text.find(':', text.empty() ? 0 : 1);  // allow a leading minus
  const auto number = [&](const std::string& s, double& v) {
    if (s.empty()) return false;
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && std::isfinite(v);
  };
  double a = 0, b = 0;
  if (colon == std::string::npos || !number(text.substr(0, colon), a) ||
      !number(text.substr(colon + 1), b))
    fail(flag, " ", text, ": expected ", form, " (two numbers separated by ':')");
  return {a, b};
}

std::vector<std::uint64_t> evenly_spaced(std::uint64_t frames, std::uint64_t count) {
  count = std::min(count, frames);
  std::vector<std::uint64_t> indices;
  for (std::uint64_t k = 0; k < count; ++k)
    indices.push_back(count == 1 ? 0
                                 : static_cast<std::uint64_t>(std::llround(
                                       static_cast<double>(k) * static_cast<double>(frames - 1) /
                                       static_cast<double>(count - 1))));
  return indices;
}

// Reads the given frames of every stack into one sample vector.
std::vector<float> gather(std::vector<FrameStack*> stacks, const std::vector<std::uint64_t>& indices) {
  std::vector<float> values, frame;
  for (FrameStack* stack : stacks) {
    frame.resize(stack->pixels());
    for (std::uint64_t i : indices) {
      stack->read(i, frame);
      values.insert(values.end(), frame.begin(), frame.end());
    }
  }
  return values;
}

std::string number_text(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

}  // namespace

int run_render(const RenderOptions& o, std::ostream& out) {
  // Flags first: cheap, and the message names the flag.
  const Colormap colormap = parse_colormap(o.colormap);
  if (o.scale < 1 || o.scale > 64) fail("--scale ", o.scale, ": must be 1 to 64");
  if (o.frame && o.contact_sheet) fail("--frame and --contact-sheet: choose one");
  if (o.range && o.percentile) fail("--range and --percentile: choose one");
  if (o.range && o.agc) fail("--range and --agc: choose one (--agc picks a range per frame)");
  if (o.contact_sheet && (o.count < 1 || o.count > 1024)) fail("--count ", o.count, ": must be 1 to 1024");
  if (o.contact_sheet && (o.columns < 1 || o.columns > 256)) fail("--columns ", o.columns, ": must be 1 to 256");
  std::optional<DisplayRange> fixed_range;
  double p_lo = 1.0, p_hi = 99.0;
  if (o.range) {
    const auto [lo, hi] = parse_pair("--range", *o.range, "LO:HI");
    if (!(hi > lo)) fail("--range ", *o.range, ": LO must be below HI");
    fixed_range = DisplayRange{lo, hi};
  }
  if (o.percentile) {
    std::tie(p_lo, p_hi) = parse_pair("--percentile", *o.percentile, "P_LO:P_HI");
    if (!(p_lo >= 0 && p_hi <= 100 && p_lo < p_hi))
      fail("--percentile ", *o.percentile, ": need 0 <= P_LO < P_HI <= 100");
  }
  if (o.output.empty()) fail("OUT.png: empty path");
  {
    std::error_code ec;
    const fs::path parent = fs::absolute(o.output).parent_path();
    if (!fs::is_directory(parent, ec))
      fail(o.output.string(), ": folder ", parent.string(), " does not exist");
    if (fs::is_directory(o.output, ec)) fail(o.output.string(), ": is a folder, expected a .png file path");
  }

  // Recordings.
  FrameStack a(o.input);
  std::optional<FrameStack> b;
  if (o.compare) {
    b.emplace(*o.compare);
    if (b->width() != a.width() || b->height() != a.height())
      fail("--compare ", o.compare->string(), ": frames are ", b->width(), "x", b->height(),
           " but ", o.input.string(), " has ", a.width(), "x", a.height(), " (the same size is required)");
  }
  if (a.frames() == 0) fail(o.input.string(), ": no frames");
  std::vector<std::uint64_t> shown;
  if (o.contact_sheet) {
    shown = evenly_spaced(a.frames(), o.count);
    if (b && b->frames() != a.frames())
      fail("--compare ", o.compare->string(), ": ", b->frames(), " frames but ", o.input.string(),
           " has ", a.frames(), " (a contact sheet compares the same frames)");
  } else {
    const std::uint64_t frame = o.frame.value_or(0);
    if (frame >= a.frames())
      fail(o.input.string(), ": --frame ", frame, ": out of range (", a.frames(), " frames, 0 to ",
           a.frames() - 1, ")");
    if (b && frame >= b->frames())
      fail(o.compare->string(), ": --frame ", frame, ": out of range (", b->frames(),
           " frames, 0 to ", b->frames() - 1, ")");
    shown = {frame};
  }
  std::vector<FrameStack*> stacks = {&a};
  if (b) stacks.push_back(&*b);

  // A display range fixed over the whole recording (unless --agc): percentiles over evenly
  // sampled frames. Each side of a comparison gets its own (the corrector rescales the signal by
  // g, so one shared range would hide the difference that matters) unless --same-range.
  std::string range_note;
  std::vector<DisplayRange> fixed_ranges;
  if (fixed_range) {
    range_note = "--range";
    fixed_ranges.assign(stacks.size(), *fixed_range);
  } else if (!o.agc) {
    const std::uint64_t sample_frames =
        std::max<std::uint64_t>(1, kRangeSampleBudget / (a.pixels() * stacks.size()));
    const auto sampled = evenly_spaced(a.frames(), sample_frames);
    if (o.same_range || stacks.size() == 1) {
      std::vector<float> values = gather(stacks, sampled);
      fixed_ranges.assign(stacks.size(), percentile_range(values, p_lo, p_hi));
    } else {
      for (FrameStack* stack : stacks) {
        std::vector<float> values = gather({stack}, sampled);
        fixed_ranges.push_back(percentile_range(values, p_lo, p_hi));
      }
    }
    range_note = "percentiles " + number_text(p_lo) + ":" + number_text(p_hi) + " over " +
                 std::to_string(sampled.size()) + " of " + std::to_string(a.frames()) + " frames" +
                 (b ? (o.same_range ? ", one range for both recordings" : ", per recording") : "");
  } else {
    range_note = "--agc: percentiles " + number_text(p_lo) + ":" + number_text(p_hi) + " per frame";
  }

  // Layout: a tile is one frame, or REC | REC2; a contact sheet is a grid of tiles.
  const std::uint64_t scale = o.scale;
  const std::uint64_t panel_w = a.width() * scale, panel_h = a.height() * scale;
  const std::uint64_t gap = std::max<std::uint64_t>(2, scale);
  const std::uint64_t tile_w = panel_w * stacks.size() + gap * (stacks.size() - 1);
  const std::uint64_t columns = std::min<std::uint64_t>(o.contact_sheet ? o.columns : 1, shown.size());
  const std::uint64_t rows = (shown.size() + columns - 1) / columns;
  const std::uint64_t sheet_gap = o.contact_sheet ? 2 * gap : 0;
  const std::uint64_t canvas_w = columns * tile_w + (columns - 1) * sheet_gap;
  const std::uint64_t canvas_h = rows * panel_h + (rows - 1) * sheet_gap;
  if (canvas_w * canvas_h > kMaxCanvasPixels)
    fail(o.output.string(), ": the image would be ", canvas_w, "x", canvas_h,
         " pixels; lower --scale or --count");
  Canvas canvas(static_cast<std::uint32_t>(canvas_w), static_cast<std::uint32_t>(canvas_h), {32, 32, 32});

  std::vector<std::vector<float>> frames(stacks.size(), std::vector<float>(a.pixels()));
  for (std::size_t k = 0; k < shown.size(); ++k) {
    for (std::size_t s = 0; s < stacks.size(); ++s) stacks[s]->read(shown[k], frames[s]);
    std::vector<DisplayRange> ranges = fixed_ranges;
    if (ranges.empty()) {  // --agc: this tile's frames (both sides of a comparison together)
      std::vector<float> values;
      for (const auto& f : frames) values.insert(values.end(), f.begin(), f.end());
      ranges.assign(stacks.size(), percentile_range(values, p_lo, p_hi));
    }
    const auto x0 = static_cast<std::uint32_t>((k % columns) * (tile_w + sheet_gap));
    const auto y0 = static_cast<std::uint32_t>((k / columns) * (panel_h + sheet_gap));
    for (std::size_t s = 0; s < stacks.size(); ++s)
      canvas.draw_frame(static_cast<std::uint32_t>(x0 + s * (panel_w + gap)), y0, frames[s],
                        a.width(), a.height(), ranges[s], colormap, o.scale);
    if (o.labels) canvas.draw_number(x0, y0, std::to_string(shown[k]), std::max<std::uint32_t>(1, o.scale));
  }
  rec::write_png_rgb8(o.output, canvas.width(), canvas.height(), canvas.rgb());

  out << "wrote " << o.output.string() << ": " << canvas.width() << "x" << canvas.height() << ", ";
  if (o.contact_sheet)
    out << shown.size() << " frames of " << a.frames() << " in " << columns << " columns";
  else
    out << "frame " << shown.front();
  out << " of " << o.input.string();
  if (b) out << " | " << o.compare->string();
  out << "; colormap " << o.colormap << "; range ";
  for (std::size_t s = 0; s < fixed_ranges.size(); ++s)
    out << (s ? " | " : "") << number_text(fixed_ranges[s].lo) << " .. " << number_text(fixed_ranges[s].hi);
  out << (fixed_ranges.empty() ? "" : " ") << "(" << range_note << ")\n";
  return kExitOk;
}

Command add_render_command(CLI::App& parent) {
  auto o = std::make_shared<RenderOptions>();
  auto frame = std::make_shared<std::uint64_t>(0);
  auto compare = std::make_shared<std::string>();
  auto range = std::make_shared<std::string>();
  auto percentile = std::make_shared<std::string>();
  CLI::App* app = add_command(
      parent, "render", "Render frames to PNG: one frame, a contact sheet, side by side with --compare",
      "Renders a recording to an 8-bit RGB PNG: one frame (--frame, default 0) or a contact sheet\n"
      "of evenly spaced frames, optionally side by side with a second recording of the same size\n"
      "(--compare, e.g. raw | corrected). The display range is the same for every frame shown:\n"
      "percentiles 1:99 over the whole recording (REC2 its own, or both one with --same-range),\n"
      "from evenly sampled frames, unless\n"
      "--range, --percentile or --agc (a range per frame) say otherwise.\n\n"
      "Examples:\n"
      "  bolo render raw out/compare.png --frame 40 --compare out/corrected --scale 3\n"
      "  bolo render out/corrected out/sheet.png --contact-sheet --count 12 --columns 4 --colormap iron");
  app->add_option("REC", o->input, "Recording folder (uint16 or float32 frames.npy)")->required();
  app->add_option("OUT.png", o->output, "PNG file to write (replaced atomically)")->required();
  CLI::Option* frame_opt = app->add_option("--frame", *frame, "Frame index to render (default 0)")
                               ->check(not_negative());
  CLI::Option* sheet_opt =
      app->add_flag("--contact-sheet", o->contact_sheet, "Tile --count evenly spaced frames in --columns columns");
  frame_opt->excludes(sheet_opt);
  CLI::Option* compare_opt =
      app->add_option("--compare", *compare, "Second recording drawn to the right of REC (same size)");
  CLI::Option* range_opt = app->add_option("--range", *range, "Fixed display range LO:HI in pixel units");
  CLI::Option* percentile_opt = app->add_option(
      "--percentile", *percentile, "Display range from percentiles P_LO:P_HI (default 1:99)");
  range_opt->excludes(percentile_opt);
  app->add_flag("--same-range", o->same_range,
                "With --compare: one display range for both recordings (default: one each)");
  app->add_flag("--agc", o->agc, "Automatic gain per frame: the percentile range of each frame shown");
  app->add_option("--colormap", o->colormap, "gray or iron (default gray)")
      ->check(CLI::IsMember({"gray", "iron"}));
  // Unsigned options take "-3" as a huge number unless the text is checked first.
  app->add_option("--scale", o->scale, "Nearest-neighbour upscale factor K, 1 to 64 (default 1)")
      ->check(not_negative());
  app->add_option("--columns", o->columns, "Contact sheet columns (default 4)")->check(not_negative());
  app->add_option("--count", o->count, "Contact sheet frames (default 16)")->check(not_negative());
  app->add_flag("--labels", o->labels, "Draw frame indices on the tiles");
  return {app, [=](std::ostream& out) {
            if (frame_opt->count()) o->frame = *frame;
            if (compare_opt->count()) o->compare = fs::path(*compare);
            if (range_opt->count()) o->range = *range;
            if (percentile_opt->count()) o->percentile = *percentile;
            return run_render(*o, out);
          }};
}

}  // namespace bolo::cli
