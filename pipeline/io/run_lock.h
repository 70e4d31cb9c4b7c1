// One run per output folder: OUT/.kurage.lock, held with flock(2) for the life of the process
// (the kernel releases it when the process ends, however it ends). The file holds the holder's
// pid and command, so that a refused run can name it. A link or anything but a regular file at
// OUT/.kurage.lock is refused, never followed.
#pragma once

#include <filesystem>
#include <string>

namespace kurage::pipeline {

class RunLock {
public:
  // Creates OUT if needed and takes the lock. Throws IoError naming OUT and the holder's pid
  // when another process holds it.
  RunLock(const std::filesystem::path& outDir, const std::string& command);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

  // True while a process holds OUT's lock (a run is writing into it); false when none does or
  // there is no lock file. Takes nothing and writes nothing.
  static bool held(const std::filesystem::path& outDir);

private:
  int fd_ = -1;
};

}  // namespace kurage::pipeline
