// Running another program (ffmpeg, ffprobe, gnuplot) from kurage.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace kurage::pipeline {

// Asked while a long piece of work runs (every 100 ms here): true ends it early. Callers pass
// pipeline::interruptPending (pipeline/interrupt.h) so that SIGINT/SIGTERM end the work.
using StopRequested = std::function<bool()>;

// What runProgram returns when `stop` ended the program.
inline constexpr int kProgramStopped = -2;

// Runs a program with arguments (no shell), its stdout and stderr captured together into
// *output; returns its exit status (127: it could not be started), or -1 when no process could be
// made or it was killed by a signal. The program is killed if kurage dies first: killed with
// SIGKILL mid-write, an orphaned ffmpeg or gnuplot went on and recreated its temporary after the
// next run had cleared the dead run's (tests/test_resume.cpp). When `stop` returns true, the
// program gets SIGTERM (SIGKILL a second later if it is still there) and runProgram returns
// kProgramStopped once it has ended.
int runProgram(const std::vector<std::string>& argv, std::string* output, const StopRequested& stop = {});

// A word for bash: single-quoted, with ' written as '\''. With `quoteAlways` false, a word of
// only characters bash takes literally (letters, digits, and _ . / - + = : , @ %) stays as it is.
std::string shellWord(const std::string& word, bool quoteAlways = true);

}  // namespace kurage::pipeline
