#include "bolo/correct/source_correction.hpp"

#include <optional>

#include "bolo/hal/frame_reader.hpp"
#include "bolo/hal/recording_player.hpp"
#include "bolo/recording/frame_row_header.hpp"
#include "corrected_output.hpp"
#include "correction_chain.hpp"
#include "frame_timing.hpp"

namespace bolo::correct {

namespace {

// The recording player behind a file: spec, else nullptr. Asked by the spec: the device backends
// are built without RTTI (board flags), so a dynamic_cast cannot ask them.
hal::RecordingPlayer* recording_player(const std::string& spec, hal::OpenedSource& source) {
  if (hal::parse_source_spec(spec).backend.scheme != "file") return nullptr;
  return &dynamic_cast<hal::RecordingPlayer&>(source.backend());
}

}  // namespace

struct SourceCorrection::Impl {
  // Forwards a frame to the chain and notes when its first line came: the frame's dequeue.
  class BeginStamp final : public fw::LineSink {
   public:
    explicit BeginStamp(fw::LineSink& next) : next_(next) {}
    Clock::time_point began() const { return began_; }

    void begin_frame(const fw::FrameHeader& header) override {
      began_ = Clock::now();
      next_.begin_frame(header);
    }
    void push_line(std::uint32_t row, fw::LineView line) override { next_.push_line(row, line); }
    void push_lines(std::uint32_t first_row, std::uint32_t count, const fw::Pixel* pixels, std::size_t width,
                    std::size_t stride) override {
      next_.push_lines(first_row, count, pixels, width, stride);
    }
    void end_frame() override { next_.end_frame(); }

   private:
    fw::LineSink& next_;
    Clock::time_point began_;
  };

  Impl(const CorrectRequest& r, hal::OpenedSource& s)
      : request(r),
        name(r.input.string()),
        source(s),
        setup(checked_setup(r)),
        player(recording_player(r.input.string(), s)),
        chain(pipeline_config(setup, s.format(), r.bad_pixels, name), request, name),
        stamp(chain.input()),
        reader(s, r.max_faults) {}

  const CorrectRequest request;
  const std::string name;
  hal::OpenedSource& source;
  const Setup setup;
  hal::RecordingPlayer* const player;  // a recording: its rows go along
  CorrectionChain chain;
  BeginStamp stamp;
  hal::FrameReader reader;
  rec::RowClock clock;
  FrameTiming timing, previous_timing;
  rec::FrameRow row;
  FrameStats stats;
  std::uint64_t frames = 0;
};

SourceCorrection::SourceCorrection(const CorrectRequest& request, hal::OpenedSource& source)
    : impl_(std::make_unique<Impl>(request, source)) {}

SourceCorrection::~SourceCorrection() = default;

SourceCorrection::Next SourceCorrection::next() {
  Impl& m = *impl_;
  const hal::FrameReader::Result r = m.reader.next(m.stamp);
  if (r == hal::FrameReader::Result::ended) return Next::ended;
  if (r == hal::FrameReader::Result::gave_up) return Next::gave_up;
  if (r == hal::FrameReader::Result::stopped) return Next::stopped;
  const std::uint64_t i = m.frames;
  const FrameTiming* previous = i == 0 ? nullptr : &m.previous_timing;
  if (i != 0) m.previous_timing = m.timing;
  m.timing = timing_from_header(m.reader.header(), m.setup.exposure, m.setup.readout, m.name, i);
  check_coefficients_at(previous, m.timing, i, m.setup.tau, m.request, m.name, "frame header");
  // The player has just delivered the frame before its position.
  m.row = m.player ? m.player->recording().rows()[m.player->position() - 1] : m.clock.row(m.reader.header(), i);
  m.stats = m.chain.finish_frame(i, m.row, m.timing, previous);
  ++m.frames;
  return Next::frame;
}

void SourceCorrection::set_stop(std::function<bool()> stop) { impl_->reader.set_stop(std::move(stop)); }

std::span<const std::uint16_t> SourceCorrection::pixels() const { return impl_->chain.pixels(); }
const rec::FrameRow& SourceCorrection::row() const { return impl_->row; }
const FrameStats& SourceCorrection::stats() const { return impl_->stats; }
SourceCorrection::Clock::time_point SourceCorrection::began() const { return impl_->stamp.began(); }
void SourceCorrection::append(rec::RecordingWriter& writer) const { impl_->chain.append(writer, impl_->row); }
std::uint64_t SourceCorrection::frames() const { return impl_->frames; }
std::uint64_t SourceCorrection::skipped() const { return impl_->reader.skipped(); }
bool SourceCorrection::from_recording() const { return impl_->player != nullptr; }

rec::RecordingInfo SourceCorrection::corrected_info() const {
  const Impl& m = *impl_;
  if (m.player) return correct::corrected_info(m.player->recording().info(), m.request, false);
  rec::RecordingInfo info = hal::recording_info_of(m.source);
  info.notes = "t_s from the device's clock, relative to the first frame";
  return correct::corrected_info(info, m.request, true);
}

std::string SourceCorrection::capture_json() const {
  return hal::source_record(impl_->name, impl_->source, impl_->clock.not_increasing()).dump(2) + "\n";
}

std::string SourceCorrection::faults() const { return hal::fault_text(impl_->source); }

}  // namespace bolo::correct
