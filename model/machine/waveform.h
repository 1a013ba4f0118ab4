// A waveform being recorded: the VCD file, and every signal traced into it, named after the
// object hierarchy (sc_object::name() + "." + the signal), so the GTKWave save file (gtkw.h) is
// written from what was actually traced.
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include <systemc>

namespace rtm {

class Waveform {
 public:
  enum class Format { Bit, Decimal, Real };
  struct Signal {
    std::string name;  ///< hierarchical, e.g. machine.pe0.search2.busy
    Format format;
    int bits;  ///< of a Decimal value
  };

  explicit Waveform(sc_core::sc_trace_file* file) : file_(file) {}

  template <class T>
  void trace(const T& v, const std::string& name) {
    sc_core::sc_trace(file_, v, name);
    signals_.push_back({name, format_of<T>(), int(8 * sizeof(typename value_of<T>::type))});
  }
  const std::vector<Signal>& signals() const { return signals_; }

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
  std::vector<Signal> signals_;
};

}  // namespace rtm
