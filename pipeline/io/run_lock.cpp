#include "pipeline/io/run_lock.h"

#include "pipeline/io/files.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace kurage::pipeline {

RunLock::RunLock(const std::filesystem::path& outDir, const std::string& command) {
  std::error_code ec;
  std::filesystem::create_directories(outDir, ec);
  if (ec) throw IoError(outDir.string() + ": cannot create the output folder: " + ec.message());
  const std::filesystem::path file = outDir / ".kurage.lock";
  // Never through a link (a link here pointing outside OUT had its target truncated), never a
  // FIFO or a device (non-blocking open, then fstat).
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0666);
  if (fd_ < 0) {
    const int error = errno;
    throw IoError(file.string() + ": cannot open the run lock: " +
                  (error == ELOOP ? std::string("it is a symbolic link; kurage writes through no link (remove it)")
                                  : std::string(std::strerror(error))));
  }
  struct stat info {};
  if (::fstat(fd_, &info) != 0 || !S_ISREG(info.st_mode)) {
    ::close(fd_);
    fd_ = -1;
    throw IoError(file.string() + ": the run lock is not a regular file (remove it)");
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    std::string holder;
    char buffer[512];
    const ssize_t n = ::pread(fd_, buffer, sizeof buffer - 1, 0);
    if (n > 0) holder.assign(buffer, size_t(n));
    while (!holder.empty() && holder.back() == '\n') holder.pop_back();
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK)
      throw IoError(outDir.string() + ": another kurage run is writing into this folder (" +
                    (holder.empty() ? std::string("holder unknown") : holder) +
                    "); wait for it to end, or choose another -o");
    throw IoError(file.string() + ": cannot take the run lock: " + std::strerror(error));
  }
  const std::string text = "pid " + std::to_string(::getpid()) + ": kurage " + command + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, text.data(), text.size(), 0) != ssize_t(text.size())) {
    // The lock itself is held; only the note naming the holder is missing.
  }
}

bool RunLock::held(const std::filesystem::path& outDir) {
  const int fd = ::open((outDir / ".kurage.lock").c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  // A shared lock conflicts only with a run's exclusive one; it is dropped with the descriptor.
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  return held;
}

RunLock::~RunLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the flock
}

}  // namespace kurage::pipeline
