// Running another program (ffmpeg, ffprobe, gnuplot) from kurage.
#pragma once

#include <string>
#include <vector>

namespace kurage::pipeline {

// Runs a program with arguments (no shell), its stdout and stderr captured together into
// *output; returns its exit status (127: it could not be started), or -1 when no process could be
// made or it was killed by a signal. The program is killed if kurage dies first: killed with
// SIGKILL mid-write, an orphaned ffmpeg or gnuplot went on and recreated its temporary after the
// next run had cleared the dead run's (tests/test_resume.cpp).
int runProgram(const std::vector<std::string>& argv, std::string* output);

}  // namespace kurage::pipeline
