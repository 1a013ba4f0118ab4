// A waveform being recorded: the VCD file, and every signal traced into it, so the GTKWave save
// file (frame/gtkw.h) is written from what was actually traced.
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include <systemc>

#include "frame/gtkw.h"

namespace rtm {

class Waveform {
 public:
  using Format = TracedSignal::Format;

  explicit Waveform(sc_core::sc_trace_file* file) : file_(file) {}

  template <class T>
  void trace(const T& v, const std::string& name) {
    sc_core::sc_trace(file_, v, name);
    signals_.push_back({name, format_of<T>(), int(8 * sizeof(typename value_of<T>::type))});
  }
  const std::vector<TracedSignal>& signals() const { return signals_; }

 private:
  template <class T>
  static constexpr Format format_of() {
    using V = typename value_of<T>::type;
    return std::is_same_v<V, bool>       ? Format::Bit
           : std::is_floating_point_v<V> ? Format::Real
                                         : Format::Decimal;
  }
  template <class T>
  struct value_of {
    using type = T;
  };
  template <class T>
  struct value_of<sc_core::sc_signal<T>> {
    using type = T;
  };

  sc_core::sc_trace_file* file_;
  std::vector<TracedSignal> signals_;
};

}  // namespace rtm
