#include "pipeline/interrupt.h"

#include <chrono>
#include <csignal>
#include <cstring>
#include <optional>

namespace kurage::pipeline {

namespace {

volatile std::sig_atomic_t receivedSignal = 0;

void onSignal(int signal) { receivedSignal = signal; }

std::string describe(int signal) {
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "signal " + std::to_string(signal);
}

}  // namespace

Interrupted::Interrupted(int signal)
    : std::runtime_error("interrupted by " + describe(signal) + "; the frames finished so far are complete"),
      signal_(signal) {}

void installInterruptHandlers() {
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;  // a second signal takes the default action
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool interruptPending() { return receivedSignal != 0; }

std::function<bool()> interruptPendingFor(double graceSeconds) {
  using Clock = std::chrono::steady_clock;
  return [graceSeconds, seen = std::optional<Clock::time_point>()]() mutable {
    if (!interruptPending()) return false;
    if (!seen) seen = Clock::now();
    return std::chrono::duration<double>(Clock::now() - *seen).count() >= graceSeconds;
  };
}

void throwIfInterrupted() {
  if (const int signal = receivedSignal) throw Interrupted(signal);
}

}  // namespace kurage::pipeline
