#include <exception>

#include "bolo/hal/frame_sink.hpp"
#include "builtin_sinks.hpp"

namespace bolo::hal {

std::vector<SinkBackend> sink_schemes() { return {detail::recording_sink(), detail::raw_sink(), detail::v4l2_sink()}; }

SinkSpec parse_sink_spec(std::string_view spec) {
  const std::vector<SinkBackend> backends = sink_schemes();
  const std::size_t colon = spec.find(':');
  const std::string_view scheme = spec.substr(0, colon);
  for (const SinkBackend& b : backends) {
    if (colon == std::string_view::npos || scheme != b.scheme) continue;
    const std::string argument(spec.substr(colon + 1));
    if (argument.empty() || (b.accepts && !b.accepts(argument)))
      throw SinkError(std::string(spec) + ": " + b.scheme + ": needs " + b.argument_help);
    return {b, argument};
  }
  std::string examples;
  for (std::size_t i = 0; i < backends.size(); ++i)
    examples += (i == 0 ? "" : i + 1 == backends.size() ? " or " : ", ") + backends[i].example();
  throw SinkError(std::string(spec) + ": unknown sink (expected " + examples + ")");
}

std::unique_ptr<FrameSink> open_sink(std::string_view spec, const SinkSetup& setup) {
  const SinkSpec parsed = parse_sink_spec(spec);
  try {
    return parsed.backend.open(std::string(spec), parsed.argument, setup);
  } catch (const SinkError&) {
    throw;
  } catch (const rec::Error&) {
    throw;
  } catch (const std::exception& e) {
    throw SinkError(std::string(spec) + ": " + e.what());
  }
}

}  // namespace bolo::hal
