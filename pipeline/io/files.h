// The one I/O layer: every file kurage writes goes through writeFileAtomic or TempFile, every
// file it reads through readFile. The guarantees (docs/design/reliability.md):
//  - a final name only ever holds a complete file: bytes go to a temporary beside the target,
//    unique to the process and created exclusively (O_EXCL), every write and the close are
//    checked, the file is fsync'ed, renamed over the target, and the folder is fsync'ed;
//  - on any failure the temporary is removed and an IoError naming the target is thrown;
//  - nothing is written through a link: temporaries are created with O_EXCL | O_NOFOLLOW, and
//    the folders under OUT come from outputFolder(), which refuses a symbolic link or a file
//    where a folder should be (a link at OUT/frames would send the frames elsewhere).
// Reads take regular files only: a FIFO, a device or a folder is an error naming it, never a
// read that blocks for ever (the file is opened non-blocking and checked with fstat first).
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace kurage::pipeline {

// A failed read or write; the message names the file.
class IoError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// A temporary file beside `target`, named ".NAME.PID.N.tmp" (unique to the process, created
// with O_EXCL so two runs never share one). commit() fsyncs it, renames it over the target and
// fsyncs the folder; the destructor removes it unless committed. Used directly when another
// program (ffmpeg) writes the bytes.
class TempFile {
public:
  explicit TempFile(std::filesystem::path target);
  ~TempFile();
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  const std::filesystem::path& path() const { return temp_; }
  const std::filesystem::path& target() const { return target_; }
  // Appends bytes; every write is checked (a full disk or a file-size limit throws).
  void write(std::string_view bytes);
  void commit();

private:
  void closeFd();
  std::filesystem::path target_;
  std::filesystem::path temp_;
  int fd_ = -1;
  bool committed_ = false;
};

// Writes `bytes` to `target` atomically (see above). Throws IoError naming the target.
void writeFileAtomic(const std::filesystem::path& target, std::string_view bytes);

// Writes text to `target` atomically. Throws IoError naming the path.
void writeTextAtomic(const std::filesystem::path& target, const std::string& text);

// Reads a whole regular file, checking every read. Throws IoError naming the path for anything
// but a regular file and for a file larger than `maxBytes`.
std::string readFile(const std::filesystem::path& path, size_t maxBytes = SIZE_MAX);
std::string readText(const std::filesystem::path& path);

// Throws IoError naming `path` unless it is a regular file (or a link to one): for readers that
// open a file by name themselves (OpenEXR, libpng), so that a FIFO is refused, not waited on.
void requireRegularFile(const std::filesystem::path& path);

// OUT/relative as a folder kurage may write into, made folder by folder as needed (OUT itself
// too; OUT may be a link, the user chose it). Throws IoError naming the path when a folder below
// OUT is a symbolic link or not a folder, or `relative` is absolute or has a ".." part.
std::filesystem::path outputFolder(const std::filesystem::path& outDir, const std::filesystem::path& relative);

// Removes the temporaries (".NAME.PID.N.tmp") in `folder` and its subfolders left by processes
// that no longer run on this machine (a run killed with SIGKILL, a power cut); returns how many.
// Only for a caller that holds the folder's RunLock: a farm task on another node has pids this
// machine cannot see.
size_t removeStaleTemporaries(const std::filesystem::path& folder);

// fsyncs a folder (so that a rename in it is durable). Throws IoError naming it.
void syncFolder(const std::filesystem::path& folder);

// "OUT/particles/0042.vdb" style names.
std::filesystem::path frameFile(const std::filesystem::path& folder, int frame, const char* extension);

}  // namespace kurage::pipeline
