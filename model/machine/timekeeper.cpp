#include "machine/timekeeper.h"

namespace rtm {

Timekeeper::Timekeeper(sc_core::sc_module_name name) : sc_module(name) { SC_THREAD(run); }

void Timekeeper::wait(const sc_core::sc_time& d, int rank, sc_core::sc_event& wake) {
  post(sc_core::sc_time_stamp() + d, rank, wake);
  sc_core::wait(wake);
}

void Timekeeper::post(const sc_core::sc_time& at, int rank, sc_core::sc_event& wake) {
  if (due_.empty() || at < due_.top().at) earlier_.notify();
  due_.push({at, rank, seq_++, &wake});
}

void Timekeeper::run() {
  for (;;) {
    if (due_.empty()) {
      sc_core::wait(earlier_);
      continue;
    }
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    if (due_.top().at > now) {
      sc_core::wait(due_.top().at - now, earlier_);
      continue;
    }
    // Immediate notifications make the sleepers runnable in this order, and the kernel runs
    // runnable processes in the order they became runnable.
    while (!due_.empty() && due_.top().at == now) {
      due_.top().wake->notify();
      due_.pop();
    }
  }
}

}  // namespace rtm
