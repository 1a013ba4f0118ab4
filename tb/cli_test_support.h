// What the whole-program tests share: a scratch folder per test, files in and out, and running a
// command with its output captured.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace rtm::test {

/// Options for a random small machine whose loop cannot deadlock: 16x16 pixels, 1 to max_pes PEs,
/// FIFOs no shallower than the search FIFO, loop credits within its depth, and random pipeline
/// depths (unit latencies) and intervals (0: unpipelined). Draws from rng in a fixed order, so a
/// seed always gives the same machines.
inline std::string random_small_machine(std::mt19937& rng, int max_pes) {
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  const int depth = pick(1, 4);
  std::ostringstream args;
  args << " --size 16x16 --pes " << pick(1, max_pes) << " --search-units " << pick(1, 6)
       << " --set search_fifo_depth=" << depth << " --set intersect_fifo_depth=" << pick(depth, 5)
       << " --set root_fifo_depth=" << pick(depth, 5)
       << " --set shade_fifo_depth=" << pick(depth, 5)
       << " --set feedback_fifo_depth=" << pick(1, 3)
       << " --set front_buffer_capacity=" << pick(1, 8) << " --set loop_credits=" << pick(0, depth);
  args << " --set dda_step_cycles=" << pick(1, 4) << " --set root_latency=" << pick(1, 14)
       << " --set shade_cycles=" << pick(1, 20) << " --set dispatch_interval=" << pick(0, 2)
       << " --set search_interval=" << pick(0, 3)
       << " --set mac_streaming=" << (pick(0, 1) ? "true" : "false")
       << " --set root_interval=" << pick(0, 2) << " --set shade_interval=" << pick(0, 3);
  return args.str();
}

/// Options for a random local memory (docs/memory.md): ports, banks, interleave, latency, width,
/// arbiter, coefficient RAM and voxel cache, from the ideal memory to one port shared by all.
inline std::string random_memory(std::mt19937& rng) {
  auto one_of = [&](std::initializer_list<const char*> v) {
    return *(v.begin() + std::uniform_int_distribution<size_t>(0, v.size() - 1)(rng));
  };
  std::ostringstream args;
  args << " --set memory_ports=" << one_of({"0", "1", "1", "2", "3"})
       << " --set memory_banks=" << one_of({"0", "1", "2", "4", "8"})
       << " --set memory_interleave_bytes=" << one_of({"4", "8", "16", "32"})
       << " --set memory_latency=" << one_of({"1", "2", "3", "8"})
       << " --set memory_bytes_per_cycle=" << one_of({"4", "8", "16"})
       << " --set memory_arbitration=" << one_of({"round_robin", "fixed_priority", "fcfs"})
       << " --set mac_ram_primitives=" << one_of({"0", "1", "2", "4", "16"})
       << " --set voxel_cache_bytes=" << one_of({"0", "0", "64", "1024"});
  return args.str();
}

/// A fresh folder per test, removed afterwards.
class Tmp {
 public:
  Tmp() {
    char tmpl[] = "/tmp/rtm-test-XXXXXX";
    dir_ = mkdtemp(tmpl);
  }
  ~Tmp() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  Tmp(const Tmp&) = delete;
  Tmp& operator=(const Tmp&) = delete;
  std::string operator/(const std::string& name) const {
    return (std::filesystem::path(dir_) / name).string();
  }

 private:
  std::string dir_;
};

inline std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

inline void spit(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

struct Proc {
  int exit_code = -1;
  std::string out, err;
};

/// Every signal a VCD declares, named as GTKWave names it: scopes and name joined by dots, then
/// the bit range of a vector (SystemC.machine.pe0.search_fifo.occupancy[31:0]).
inline std::vector<std::string> vcd_signals(const std::string& vcd) {
  std::vector<std::string> scopes, names;
  std::istringstream words(vcd.substr(0, vcd.find("$enddefinitions")));
  for (std::string w; words >> w;) {
    if (w == "$scope") {
      std::string kind, name;
      words >> kind >> name;
      scopes.push_back(name);
    } else if (w == "$upscope") {
      scopes.pop_back();
    } else if (w == "$var") {
      std::string type, bits, id, name, range;
      words >> type >> bits >> id >> name >> range;
      std::string full;
      for (const std::string& s : scopes) full += s + ".";
      names.push_back(full + name + (range != "$end" ? range : ""));
    }
  }
  return names;
}

/// Runs a shell command with stdout and stderr captured in `tmp` (no stdin).
inline Proc sh(const std::string& cmd, const Tmp& tmp) {
  const std::string out = tmp / "stdout.txt", err = tmp / "stderr.txt";
  const int status = std::system((cmd + " >" + out + " 2>" + err + " </dev/null").c_str());
  Proc r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

/// Runs the rtm binary under test.
inline Proc run_rtm(const std::string& args, const Tmp& tmp) {
  return sh(std::string(RTM_BINARY) + " " + args, tmp);
}

/// `rtm render ARGS`, the image to `<name>.exr`, the ID map to `<name>-id.exr`; returns the stats
/// (null, with a test failure, if the render failed).
inline nlohmann::json render(const Tmp& tmp, const std::string& name, const std::string& args) {
  const Proc r =
      run_rtm("render " + args + " --out " + (tmp / (name + ".exr")) + " --id-map " +
                  (tmp / (name + "-id.exr")) + " --stats " + (tmp / (name + ".json")) + " -q",
              tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? nlohmann::json::parse(slurp(tmp / (name + ".json"))) : nlohmann::json();
}

}  // namespace rtm::test
