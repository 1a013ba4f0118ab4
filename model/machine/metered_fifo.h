// sc_fifo that keeps its own occupancy statistics and a traceable occupancy copy
// (sc_fifo::trace does nothing in a release build of SystemC), and that several units may share:
// the replicated search units all read the front buffer's FIFO, and several stages write the
// paths into the shading stage and back into the front buffer. sc_fifo's read and write wait
// until they can proceed, so sharing is safe under SystemC's cooperative scheduling.
#pragma once

#include <cstdint>
#include <string>

#include <systemc>

#include "machine/trace_window.h"

namespace rtm {

struct FifoStats {
  std::string kind;        ///< e.g. "search", for grouping across PEs
  int depth = 0;
  int peak = 0;
  double occupancy_time = 0;  ///< ∫ occupancy dt, in seconds
  uint64_t writes = 0;
};

template <class T>
class MeteredFifo : public sc_core::sc_fifo<T> {
 public:
  MeteredFifo(const char* name, int depth, const char* kind) : sc_core::sc_fifo<T>(name, depth) {
    stats_.kind = kind;
    stats_.depth = depth;
  }

  /// Any number of reader and writer ports (plain sc_fifo allows one of each).
  void register_port(sc_core::sc_port_base&, const char*) override {}

  void write(const T& v) override {
    sc_core::sc_fifo<T>::write(v);
    change(+1);
    ++stats_.writes;
  }
  bool nb_write(const T& v) override {
    if (!sc_core::sc_fifo<T>::nb_write(v)) return false;
    change(+1);
    ++stats_.writes;
    return true;
  }
  void read(T& v) override {
    sc_core::sc_fifo<T>::read(v);
    change(-1);
  }
  T read() override {
    T v;
    read(v);
    return v;
  }
  bool nb_read(T& v) override {
    if (!sc_core::sc_fifo<T>::nb_read(v)) return false;
    change(-1);
    return true;
  }

  int occupancy() const { return occupancy_; }
  /// Closes the time integral at the end of simulation.
  const FifoStats& stats() {
    change(0);
    stats_.occupancy_time = double(area_) * sc_core::sc_get_time_resolution().to_seconds();
    return stats_;
  }
  /// Traces the occupancy; only changes inside the waveform window reach the file.
  void trace(sc_core::sc_trace_file* tf, const std::string& name, const TraceWindow* window) {
    window_ = window;
    sc_core::sc_trace(tf, traced_, name);
  }

 private:
  void change(int delta) {
    const sc_dt::uint64 now = sc_core::sc_time_stamp().value();
    area_ += sc_dt::uint64(occupancy_) * (now - last_change_);
    last_change_ = now;
    occupancy_ += delta;
    if (occupancy_ > stats_.peak) stats_.peak = occupancy_;
    if (window_ && window_->now()) traced_ = occupancy_;
  }

  FifoStats stats_;
  int occupancy_ = 0;
  int traced_ = 0;
  const TraceWindow* window_ = nullptr;
  sc_dt::uint64 last_change_ = 0;  ///< in time-resolution units
  sc_dt::uint64 area_ = 0;         ///< ∫ occupancy dt, in time-resolution units
};

}  // namespace rtm
