#include "pipeline/io/files.h"

#include <atomic>
#include <csignal>
#include <vector>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace kurage::pipeline {

namespace fs = std::filesystem;

namespace {

std::string errnoText(int error) { return std::strerror(error); }

[[noreturn]] void fail(const fs::path& target, const std::string& what, int error) {
  throw IoError(target.string() + ": " + what + ": " + errnoText(error));
}

// Distinguishes the temporaries of one process (threads included).
std::atomic<unsigned long> temporaryCounter{0};

}  // namespace

TempFile::TempFile(fs::path target) : target_(std::move(target)) {
  const fs::path folder = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  for (int attempt = 0; attempt < 100; ++attempt) {
    // Built by appending: GCC 12 gives a false -Wrestrict for "." + std::string.
    std::string name(1, '.');
    name += target_.filename().string();
    name += '.';
    name += std::to_string(::getpid());
    name += '.';
    name += std::to_string(temporaryCounter++);
    name += ".tmp";
    temp_ = folder / name;
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd_ >= 0) return;
    if (errno != EEXIST) fail(target_, "cannot create the temporary file " + temp_.string(), errno);
  }
  fail(target_, "cannot create a unique temporary file", EEXIST);
}

TempFile::~TempFile() {
  closeFd();
  if (!committed_) ::unlink(temp_.c_str());
}

void TempFile::closeFd() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void TempFile::write(std::string_view bytes) {
  if (fd_ < 0) throw IoError(target_.string() + ": write after close");
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      fail(target_, "cannot write", errno);
    }
    if (n == 0) fail(target_, "cannot write (no progress)", EIO);
    bytes.remove_prefix(size_t(n));
  }
}

void TempFile::commit() {
  if (fd_ < 0) {  // written by another program: reopen to fsync what it wrote
    fd_ = ::open(temp_.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd_ < 0) fail(target_, "cannot reopen " + temp_.string(), errno);
  }
  if (::fsync(fd_) != 0) fail(target_, "cannot sync", errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(target_, "cannot close", errno);
  if (::rename(temp_.c_str(), target_.c_str()) != 0) fail(target_, "cannot rename into place", errno);
  committed_ = true;
  syncFolder(target_.has_parent_path() ? target_.parent_path() : fs::path("."));
}

void syncFolder(const fs::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) fail(folder, "cannot open the folder to sync it", errno);
  const int synced = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (synced != 0 && error != EINVAL) fail(folder, "cannot sync the folder", error);
}

void writeFileAtomic(const fs::path& target, std::string_view bytes) {
  TempFile file(target);
  file.write(bytes);
  file.commit();
}

void writeTextAtomic(const fs::path& target, const std::string& text) { writeFileAtomic(target, text); }

std::string readFile(const fs::path& path, size_t maxBytes) {
  // Non-blocking, so that opening a FIFO returns at once and fstat can refuse it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) fail(path, "cannot open", errno);
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
    ::close(fd);
    throw IoError(path.string() + ": not a regular file (a FIFO, a device or a folder cannot be read)");
  }
  if (uint64_t(info.st_size) > maxBytes) {
    ::close(fd);
    throw IoError(path.string() + ": " + std::to_string(info.st_size) + " bytes, more than the " +
                  std::to_string(maxBytes) + " such a file may have");
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string bytes;
  bytes.reserve(size_t(info.st_size));
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      fail(path, "cannot read", error);
    }
    if (n == 0) break;
    if (bytes.size() + size_t(n) > maxBytes) {  // grew while being read
      ::close(fd);
      throw IoError(path.string() + ": more than the " + std::to_string(maxBytes) + " bytes such a file may have");
    }
    bytes.append(buffer, size_t(n));
  }
  ::close(fd);
  return bytes;
}

void requireRegularFile(const fs::path& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) fail(path, "cannot open", errno);
  if (!S_ISREG(info.st_mode))
    throw IoError(path.string() + ": not a regular file (a FIFO, a device or a folder cannot be read)");
}

std::string readText(const fs::path& path) { return readFile(path); }

fs::path outputFolder(const fs::path& outDir, const fs::path& relative) {
  if (relative.is_absolute()) throw IoError((outDir / relative).string() + ": not a folder inside " + outDir.string());
  std::error_code ec;
  fs::create_directories(outDir, ec);
  if (ec) throw IoError(outDir.string() + ": cannot create the output folder: " + ec.message());
  fs::path folder = outDir;
  for (const fs::path& part : relative) {
    if (part.empty() || part == ".") continue;
    folder /= part;
    if (part == "..") throw IoError(folder.string() + ": not a folder inside " + outDir.string());
    if (::mkdir(folder.c_str(), 0777) != 0 && errno != EEXIST) fail(folder, "cannot create the folder", errno);
    struct stat info {};
    if (::lstat(folder.c_str(), &info) != 0) fail(folder, "cannot inspect the folder", errno);
    if (S_ISLNK(info.st_mode))
      throw IoError(folder.string() + ": is a symbolic link; kurage writes only into real folders inside " +
                    outDir.string() + " (remove the link)");
    if (!S_ISDIR(info.st_mode)) throw IoError(folder.string() + ": exists and is not a folder");
  }
  return folder;
}

fs::path frameFile(const fs::path& folder, int frame, const char* extension) {
  char name[32];
  std::snprintf(name, sizeof name, "%04d.%s", frame, extension);
  return folder / name;
}

size_t removeStaleTemporaries(const fs::path& folder) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) return 0;
  std::vector<fs::path> stale;
  for (auto it = fs::recursive_directory_iterator(folder, error); !error && it != fs::recursive_directory_iterator();
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.size() < 6 || name[0] != '.' || name.substr(name.size() - 4) != ".tmp") continue;
    // ".NAME.PID.N.tmp": the pid is the second-to-last dotted field before "tmp".
    const size_t counterDot = name.rfind('.', name.size() - 5);
    if (counterDot == std::string::npos || counterDot == 0) continue;
    const size_t pidDot = name.rfind('.', counterDot - 1);
    if (pidDot == std::string::npos) continue;
    const std::string pidText = name.substr(pidDot + 1, counterDot - pidDot - 1);
    if (pidText.empty() || pidText.find_first_not_of("0123456789") != std::string::npos || pidText.size() > 9) continue;
    const pid_t pid = pid_t(std::stol(pidText));
    const bool alive = ::kill(pid, 0) == 0 || errno != ESRCH;  // EPERM: another user's live process
    if (pid == ::getpid() || alive) continue;
    stale.push_back(it->path());
  }
  size_t removed = 0;
  for (const fs::path& p : stale) removed += fs::remove(p, error) ? 1 : 0;
  return removed;
}

}  // namespace kurage::pipeline
