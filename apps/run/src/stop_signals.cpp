#include "bolo/run/stop_signals.hpp"

#include <csignal>

namespace bolo::run {
namespace {

volatile std::sig_atomic_t g_received = 0;

void note_signal(int signal) { g_received = signal; }

struct Saved {
  struct sigaction interrupt {}, terminate{}, pipe{};
};
Saved g_saved;

}  // namespace

StopSignals::StopSignals() {
  g_received = 0;
  struct sigaction stop {};
  stop.sa_handler = note_signal;
  sigemptyset(&stop.sa_mask);
  stop.sa_flags = SA_RESETHAND;  // poll() and read() are interrupted, not restarted: the loop sees it sooner
  sigaction(SIGINT, &stop, &g_saved.interrupt);
  sigaction(SIGTERM, &stop, &g_saved.terminate);
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGPIPE, &ignore, &g_saved.pipe);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &g_saved.interrupt, nullptr);
  sigaction(SIGTERM, &g_saved.terminate, nullptr);
  sigaction(SIGPIPE, &g_saved.pipe, nullptr);
}

int StopSignals::received() { return g_received; }

std::string signal_name(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal);
}

}  // namespace bolo::run
