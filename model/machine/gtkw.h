// The GTKWave save file for a waveform: every signal that was traced, grouped by PE and unit
// (FIFO occupancies of a PE in a group of their own), in the order they were traced.
#pragma once

#include <string>

#include "machine/waveform.h"

namespace rtm {

void write_gtkw(const std::string& gtkw_path, const std::string& vcd_path, const Waveform& wave);

}  // namespace rtm
