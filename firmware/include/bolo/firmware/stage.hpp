#pragma once
// A pipeline stage: a LineSink that pushes its output lines into the next LineSink.

#include "bolo/core/line_sink.hpp"

namespace bolo::fw {

class Stage : public LineSink {
 public:
  explicit Stage(LineSink& next) : next_(&next) {}
  void connect(LineSink& next) { next_ = &next; }

 protected:
  ~Stage() = default;
  LineSink& next() { return *next_; }

 private:
  LineSink* next_;
};

}  // namespace bolo::fw
