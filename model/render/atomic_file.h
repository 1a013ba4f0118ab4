// Writing a file so that a failure never leaves a partial one behind: write a temporary beside
// it, then rename. A temporary's name says it is partial and who writes it
// (".name.partial-HOST-PID.ext"), so one a killed process left behind is recognised and removed.
#pragma once

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace rtm {

/// "partial-HOST-PID": marks a file this process is writing.
inline std::string partial_tag() {
  char host[256] = "";
  if (gethostname(host, sizeof host - 1) != 0 || !*host) host[0] = '?', host[1] = 0;
  for (char* c = host; *c; ++c)
    if (*c == '/' || *c == '-') *c = '_';  // the last '-' separates host and PID
  return std::string("partial-") + host + "-" + std::to_string(getpid());
}

/// A temporary name beside `path`, keeping its extension (OpenImageIO picks the format by it).
inline std::string temporary_beside(const std::string& path) {
  const std::filesystem::path p(path);
  return (p.parent_path() /
          ("." + p.stem().string() + "." + partial_tag() + p.extension().string()))
      .string();
}

/// Whether a file named `name` is a temporary whose writer is gone: written by a process of this
/// host that no longer runs, or (another host's, which cannot be asked) last changed over a day
/// ago. Names without a tag are never abandoned; "partial-PID" (no host) is this host's.
inline bool abandoned_partial(const std::string& name, std::filesystem::file_time_type changed) {
  const size_t at = name.rfind("partial-");
  if (at == std::string::npos) return false;
  const std::string rest = name.substr(at + 8);  // HOST-PID[.ext] or PID[.ext]
  const size_t dash = rest.rfind('-');
  const std::string host = dash == std::string::npos ? std::string() : rest.substr(0, dash);
  const std::string pid_text = dash == std::string::npos ? rest : rest.substr(dash + 1);
  char* end = nullptr;
  const long pid = std::strtol(pid_text.c_str(), &end, 10);
  if (end == pid_text.c_str() || pid <= 0 || (*end && *end != '.')) return false;
  const std::string mine = partial_tag();
  const std::string my_host = mine.substr(8, mine.rfind('-') - 8);
  if (host.empty() || host == my_host)
    return pid != long(getpid()) && kill(pid_t(pid), 0) != 0 && errno == ESRCH;
  return std::filesystem::file_time_type::clock::now() - changed > std::chrono::hours(24);
}

/// Removes the abandoned temporaries of `path` (any writer's ".stem.partial-*.ext" beside it).
inline void remove_abandoned_partials(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const std::string prefix = "." + p.stem().string() + ".partial-";
  std::error_code ec;
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0 || it->path().extension() != p.extension()) continue;
    std::error_code ec2;
    if (abandoned_partial(name, fs::last_write_time(it->path(), ec2)) && !ec2)
      fs::remove(it->path(), ec2);
  }
}

/// Writes with `write(tmp)` then renames over `path`; removes the temporary on any failure.
template <class Fn>
void commit_atomically(const std::string& path, Fn write) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (const fs::path parent = fs::path(path).parent_path(); !parent.empty())
    fs::create_directories(parent, ec);
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
