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
#include "machine/waveform.h"

namespace rtm {

struct FifoStats {
  std::string kind;        ///< e.g. "search", for grouping across PEs
  int depth = 0;
  int peak = 0;
  double occupancy_time = 0;  ///< ∫ occupancy dt, in seconds
};

/// A FIFO's occupancy as it changes over time, and the statistics it gives; times in SystemC
/// time-resolution units. Shared by MeteredFifo and the PE engine's FIFOs.
struct FifoMeter {
  FifoStats stats;
  int occupancy = 0;
  uint64_t last_change = 0;
  uint64_t area = 0;  ///< ∫ occupancy dt

  FifoMeter(const char* kind, int depth) {
    stats.kind = kind;
    stats.depth = depth;
  }
  void change(int delta, uint64_t now) {
    area += uint64_t(occupancy) * (now - last_change);
    last_change = now;
    occupancy += delta;
    if (occupancy > stats.peak) stats.peak = occupancy;
  }
  /// The statistics, with the time integral closed at `now`.
  const FifoStats& close(uint64_t now) {
    change(0, now);
    stats.occupancy_time = double(area) * sc_core::sc_get_time_resolution().to_seconds();
    return stats;
  }
};

template <class T>
class MeteredFifo : public sc_core::sc_fifo<T> {
 public:
  MeteredFifo(const char* name, int depth, const char* kind) : sc_core::sc_fifo<T>(name, depth), meter_(kind, depth) {}

  /// Any number of reader and writer ports (plain sc_fifo allows one of each).
  void register_port(sc_core::sc_port_base&, const char*) override {}

  void write(const T& v) override {
    sc_core::sc_fifo<T>::write(v);
    change(+1);
  }
  bool nb_write(const T& v) override {
    if (!sc_core::sc_fifo<T>::nb_write(v)) return false;
    change(+1);
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

  int occupancy() const { return meter_.occupancy; }
  /// Closes the time integral at the end of simulation.
  const FifoStats& stats() { return meter_.close(sc_core::sc_time_stamp().value()); }
  /// Traces the occupancy; only changes inside the waveform window reach the file.
  void trace(Waveform& wave, const std::string& name, const TraceWindow* window) {
    window_ = window;
    wave.trace(traced_, name);
  }

 private:
  void change(int delta) {
    meter_.change(delta, sc_core::sc_time_stamp().value());
    if (window_ && window_->now()) traced_ = meter_.occupancy;
  }

  FifoMeter meter_;
  int traced_ = 0;
  const TraceWindow* window_ = nullptr;
};

}  // namespace rtm
