// The temporaries this process is writing (atomic_file.h names them), so that SIGINT, SIGTERM or
// SIGHUP removes them before the process dies of the signal: an interrupted run leaves nothing
// half-written, under a final name or a temporary one. SIGKILL cannot be caught: what it leaves
// is a temporary whose name says it is partial and whose writer is gone (abandoned_partial).
#pragma once

#include <string>

namespace rtm {

/// Registers `path` as being written for as long as the object lives. The destructor removes the
/// file if it is still there (a failure before commit); commit() renames it over its final name.
class PartialFile {
 public:
  explicit PartialFile(std::string path);
  ~PartialFile();
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;

  const std::string& path() const { return path_; }
  /// Renames the file over `final_path`; throws std::runtime_error naming it if that fails.
  void commit(const std::string& final_path);

 private:
  std::string path_;
  int slot_ = -1;  ///< in the registry the signal handler reads; -1: not registered (all in use)
};

/// Installs the handlers (idempotent). Each removes every registered file, writes one line saying
/// so to stderr, and re-raises the signal with its default action, so the process ends killed by
/// it (a shell reports 130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP). Everything it calls is
/// async-signal-safe (unlink, write, sigaction, raise).
void remove_partial_files_on_signals();

}  // namespace rtm
