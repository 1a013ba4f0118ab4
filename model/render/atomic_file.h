// Writing a file so that a failure never leaves a partial one behind: write a temporary beside
// it, then rename.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unistd.h>

namespace rtm {

/// A temporary name beside `path`, keeping its extension (OpenImageIO picks the format by it).
inline std::string temporary_beside(const std::string& path) {
  const std::filesystem::path p(path);
  return (p.parent_path() / ("." + p.stem().string() + ".partial-" + std::to_string(getpid()) + p.extension().string()))
      .string();
}

/// Writes with `write(tmp)` then renames over `path`; removes the temporary on any failure.
template <class Fn>
void commit_atomically(const std::string& path, Fn write) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (const fs::path parent = fs::path(path).parent_path(); !parent.empty()) fs::create_directories(parent, ec);
  const std::string tmp = temporary_beside(path);
  try {
    write(tmp);
    fs::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path + ": cannot write: " + ec.message());
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

}  // namespace rtm
