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
#include "units/fifo_meter.h"

namespace rtm {

template <class T>
class MeteredFifo : public sc_core::sc_fifo<T> {
 public:
  MeteredFifo(const char* name, int depth, const char* kind)
      : sc_core::sc_fifo<T>(name, depth), meter_(kind, depth) {}

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
  FifoMeter& meter() { return meter_; }
  /// Closes the time integral at the end of simulation.
  const FifoStats& stats() {
    return meter_.close(sc_core::sc_time_stamp().value(),
                        sc_core::sc_get_time_resolution().to_seconds());
  }
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
