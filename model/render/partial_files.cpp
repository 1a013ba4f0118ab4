#include "render/partial_files.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace rtm {
namespace {

// A fixed table, so the handler needs neither locks nor the heap: a slot is claimed, its path
// copied in, then marked live; the handler unlinks every live path.
constexpr int kSlots = 32;
constexpr size_t kPathBytes = 4096;
struct Slot {
  std::atomic<bool> claimed{false};
  std::atomic<bool> live{false};
  char path[kPathBytes];
};
Slot slots[kSlots];
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler reads the flags");

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

void write_text(const char* s) {
  const ssize_t ignored = ::write(2, s, std::strlen(s));
  (void)ignored;
}

extern "C" void on_signal(int sig) {
  int removed = 0;
  for (Slot& s : slots)
    if (s.live.load(std::memory_order_acquire)) removed += ::unlink(s.path) == 0;
  write_text(sig == SIGINT    ? "\nrtm: interrupted (SIGINT)"
             : sig == SIGTERM ? "\nrtm: terminated (SIGTERM)"
                              : "\nrtm: hung up (SIGHUP)");
  write_text(removed ? "; its partial output files are removed\n" : "\n");
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(sig, &dfl, nullptr);
  raise(sig);  // delivered, with the default action, when this handler returns
}

}  // namespace

PartialFile::PartialFile(std::string path) : path_(std::move(path)) {
  if (path_.size() >= kPathBytes) return;
  for (int i = 0; i < kSlots; ++i) {
    bool expected = false;
    if (!slots[i].claimed.compare_exchange_strong(expected, true)) continue;
    std::memcpy(slots[i].path, path_.c_str(), path_.size() + 1);
    slots[i].live.store(true, std::memory_order_release);
    slot_ = i;
    return;
  }
}

PartialFile::~PartialFile() {
  std::error_code ec;
  std::filesystem::remove(path_, ec);  // nothing there once committed
  if (slot_ >= 0) {
    slots[slot_].live.store(false, std::memory_order_release);
    slots[slot_].claimed.store(false, std::memory_order_release);
  }
}

void PartialFile::commit(const std::string& final_path) {
  std::error_code ec;
  std::filesystem::rename(path_, final_path, ec);
  if (ec) throw std::runtime_error(final_path + ": cannot write: " + ec.message());
}

void remove_partial_files_on_signals() {
  static const bool installed = [] {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (int s : kSignals) sigaddset(&sa.sa_mask, s);  // one handler at a time
    for (int s : kSignals) sigaction(s, &sa, nullptr);
    return true;
  }();
  (void)installed;
}

}  // namespace rtm
