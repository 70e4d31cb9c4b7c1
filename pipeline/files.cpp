#include "pipeline/files.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace kurage::pipeline {

std::filesystem::path temporaryPathFor(const std::filesystem::path& target) {
  std::filesystem::path tmp = target;
  tmp += ".tmp";
  return tmp;
}

void writeTextAtomic(const std::filesystem::path& target, const std::string& text) {
  const std::filesystem::path tmp = temporaryPathFor(target);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(tmp, ignored);
      throw std::runtime_error(target.string() + ": cannot write");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, target, ec);
  if (ec) throw std::runtime_error(target.string() + ": cannot rename into place: " + ec.message());
}

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::filesystem::path frameFile(const std::filesystem::path& folder, int frame, const char* extension) {
  char name[32];
  std::snprintf(name, sizeof name, "%04d.%s", frame, extension);
  return folder / name;
}

}  // namespace kurage::pipeline
