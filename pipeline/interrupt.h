// SIGINT and SIGTERM end a run cleanly: the handler only records the signal (and restores the
// default action, so a second Ctrl-C ends the process at once; every final file is complete
// either way, pipeline/io). The stages check between frames, the simulation between steps and
// solver iterations, the renderer between pixels, and ffmpeg is ended, so a run stops within a
// second or two wherever it is; they throw Interrupted, the stage command records "interrupted"
// in run.json, and main() exits with 128 + the signal number.
// The recorded signal is the one piece of process-wide state in kurage: a signal handler can
// reach nothing else.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

namespace kurage::pipeline {

class Interrupted : public std::runtime_error {
public:
  explicit Interrupted(int signal);
  int signal() const { return signal_; }

private:
  int signal_;
};

// Installs the handlers for SIGINT and SIGTERM.
void installInterruptHandlers();
// Throws Interrupted if a signal arrived since installInterruptHandlers().
void throwIfInterrupted();
// True if a signal arrived (for a stage that saves its state before throwIfInterrupted()).
bool interruptPending();
// A check that is true once a signal has been pending for `graceSeconds` (measured from the first
// call that saw it): work that can finish within the grace finishes, longer work is ended.
std::function<bool()> interruptPendingFor(double graceSeconds);

}  // namespace kurage::pipeline
