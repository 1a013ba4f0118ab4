// Sweep tests: run scripts/sweep (GNU parallel, one rtm per configuration) and scripts/plot-sweep
// as a user would, and check the CSV, the per-run files, resuming after a kill, failed runs and
// the plots.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using namespace rtm::test;

const std::string kSource = RTM_SOURCE_DIR;
const std::string kSweep = kSource + "/scripts/sweep";
const std::string kPlot = kSource + "/scripts/plot-sweep";
const std::string kScenes = kSource + "/scenes/spd";

/// The CSV columns when the spec has no `set` keys, in their documented order.
const std::vector<std::string> kColumns = {
    "run_id", "status", "error", "scene", "width", "height", "pes", "partition", "search_units", "timing",
    "precision", "cycles", "wall_seconds", "error_rmse", "error_psnr_db", "error_max_abs",
    "error_pixels_over_1_255", "rays_primary", "rays_shadow", "rays_reflected", "rays_transmitted",
    "util_front_buffer", "util_search", "util_mac", "util_root", "util_shading", "load_imbalance",
    "host_preprocess_cycles", "transfer_cycles", "pe_cycles", "gather_cycles", "link_busy_cycles",
    "bottleneck", "mac_bound_cycles", "cycles_over_mac_bound", "sim_time_ns", "voxel_steps",
    "intersection_tests", "mac_products", "mac_busy_cycles", "pe_util_front_buffer", "pe_util_search",
    "pe_util_mac", "pe_util_root", "pe_util_shading", "pe_util_credit_stall", "exit_code", "host",
    "scene_file"};
const std::vector<std::string> kPlots = {"cycles.png", "speedup.png", "utilisation.png",
                                         "pe_utilisation.png", "load_imbalance.png", "phases.png"};

std::string sweep_cmd(const std::string& spec, const std::string& out, const std::string& extra = "") {
  return kSweep + " " + spec + " --out " + out + " --rtm " + RTM_BINARY + " " + extra;
}

/// RFC 4180 CSV: a header and rows as column -> value.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
};

Csv read_csv(const std::string& path) {
  const std::string text = slurp(path);
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record;
  std::string field;
  bool quoted = false, any = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = any = true;
    } else if (c == ',') {
      record.push_back(field);
      field.clear();
      any = true;
    } else if (c == '\n') {
      record.push_back(field);
      records.push_back(record);
      record.clear();
      field.clear();
      any = false;
    } else if (c != '\r') {
      field += c;
      any = true;
    }
  }
  if (any) {
    record.push_back(field);
    records.push_back(record);
  }
  Csv csv;
  if (records.empty()) return csv;
  csv.header = records[0];
  for (size_t r = 1; r < records.size(); ++r) {
    EXPECT_EQ(records[r].size(), csv.header.size()) << "row " << r << " of " << path;
    std::map<std::string, std::string> row;
    for (size_t c = 0; c < csv.header.size() && c < records[r].size(); ++c) row[csv.header[c]] = records[r][c];
    csv.rows.push_back(row);
  }
  return csv;
}

size_t data_rows(const std::string& path) {
  std::ifstream f(path);
  size_t lines = 0;
  for (std::string l; std::getline(f, l);) lines += !l.empty();
  return lines ? lines - 1 : 0;
}

bool is_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}

/// Checks a PNG: the signature and an IHDR of a plausible plot size.
void expect_png(const std::string& path) {
  ASSERT_TRUE(fs::exists(path)) << path;
  const std::string png = slurp(path);
  ASSERT_GT(png.size(), 5000u) << path;
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
  EXPECT_EQ(png.substr(12, 4), "IHDR") << path;
  auto be32 = [&](size_t at) {
    return (uint32_t(uint8_t(png[at])) << 24) | (uint32_t(uint8_t(png[at + 1])) << 16) |
           (uint32_t(uint8_t(png[at + 2])) << 8) | uint32_t(uint8_t(png[at + 3]));
  };
  EXPECT_GT(be32(16), 300u) << path;  // width
  EXPECT_GT(be32(20), 200u) << path;  // height
}

/// Processes of a session that are still alive (zombies don't count).
std::vector<int> live_in_session(int sid) {
  std::vector<int> pids;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = slurp(e.path() / "stat");
    const size_t paren = stat.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream rest(stat.substr(paren + 2));
    char state;
    int ppid, pgrp, session;
    if (!(rest >> state >> ppid >> pgrp >> session)) continue;
    if (session == sid && state != 'Z' && state != 'X') pids.push_back(std::stoi(name));
  }
  return pids;
}

}  // namespace

// The tiny example sweep: two scenes x three PE counts -> six ok rows, their JSON, the plots.
TEST(Sweep, TinyExampleGivesOneOkRowPerConfiguration) {
  Tmp tmp;
  const std::string out = tmp / "tiny";
  const Proc r = sh(sweep_cmd(kSource + "/scripts/sweep-examples/tiny.yaml", out, "--jobs 2"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("[6/6] "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("6 rows: 6 ok"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(out + "/results.csv"), std::string::npos) << r.out;

  const Csv csv = read_csv(out + "/results.csv");
  EXPECT_EQ(csv.header, kColumns);
  ASSERT_EQ(csv.rows.size(), 6u);
  std::set<std::string> ids;
  std::set<std::pair<std::string, int>> configs;
  for (const auto& row : csv.rows) {
    ids.insert(row.at("run_id"));
    configs.insert({row.at("scene"), std::stoi(row.at("pes"))});
    EXPECT_EQ(row.at("status"), "ok") << row.at("run_id") << ": " << row.at("error");
    EXPECT_EQ(row.at("error"), "");
    EXPECT_EQ(row.at("width"), "32");
    EXPECT_EQ(row.at("height"), "32");
    EXPECT_EQ(row.at("partition"), "scanlines");
    EXPECT_EQ(row.at("exit_code"), "0");
    ASSERT_TRUE(is_number(row.at("cycles"))) << row.at("cycles");
    EXPECT_GT(std::stod(row.at("cycles")), 0);
    EXPECT_EQ(row.at("rays_primary"), "1024");
    for (const char* c : {"wall_seconds", "error_rmse", "util_mac", "load_imbalance", "host_preprocess_cycles",
                          "transfer_cycles", "pe_cycles", "gather_cycles", "link_busy_cycles"})
      EXPECT_TRUE(is_number(row.at(c))) << c << " = '" << row.at(c) << "'";
    // The phases add up to the frame.
    const double phases = std::stod(row.at("host_preprocess_cycles")) + std::stod(row.at("transfer_cycles")) +
                          std::stod(row.at("pe_cycles")) + std::stod(row.at("gather_cycles"));
    EXPECT_DOUBLE_EQ(phases, std::stod(row.at("cycles")));
    // The row matches the run's own statistics, kept in runs/.
    const std::string stats_path = out + "/runs/" + row.at("run_id") + ".json";
    ASSERT_TRUE(fs::exists(stats_path)) << stats_path;
    const json stats = json::parse(slurp(stats_path));
    EXPECT_EQ(stats["cycles"].get<double>(), std::stod(row.at("cycles")));
    EXPECT_EQ(stats["pes"].get<int>(), std::stoi(row.at("pes")));
    EXPECT_TRUE(fs::exists(out + "/runs/" + row.at("run_id") + ".err"));
    EXPECT_TRUE(fs::exists(out + "/runs/" + row.at("run_id") + ".png"));
  }
  EXPECT_EQ(ids.size(), 6u);
  const std::set<std::pair<std::string, int>> want = {{"balls-1", 1}, {"balls-1", 2}, {"balls-1", 4},
                                                      {"rings-1", 1}, {"rings-1", 2}, {"rings-1", 4}};
  EXPECT_EQ(configs, want);
  // More PEs, fewer cycles on these scenes.
  std::map<std::pair<std::string, int>, double> cycles;
  for (const auto& row : csv.rows) cycles[{row.at("scene"), std::stoi(row.at("pes"))}] = std::stod(row.at("cycles"));
  for (const std::string scene : {"balls-1", "rings-1"}) {
    EXPECT_LT((cycles[{scene, 2}]), (cycles[{scene, 1}])) << scene;
    EXPECT_LT((cycles[{scene, 4}]), (cycles[{scene, 2}])) << scene;
  }
  for (const auto& p : kPlots) expect_png(out + "/plots/" + p);

  // Running it again finds everything done and runs nothing.
  const Proc again = sh(sweep_cmd(kSource + "/scripts/sweep-examples/tiny.yaml", out, "--jobs 2 --no-plots"), tmp);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("6 already done"), std::string::npos) << again.out;
  EXPECT_EQ(again.out.find("[1/6]"), std::string::npos) << again.out;
  EXPECT_EQ(read_csv(out + "/results.csv").rows.size(), 6u);
}

// Killed after two rows (the whole process group, as a hard interrupt), then rerun: every run
// exactly once, the finished ones not run again.
TEST(Sweep, AKilledSweepResumesWithoutRepeatingOrDroppingRuns) {
  Tmp tmp;
  spit(tmp / "spec.yaml", "name: resume\nscene_dir: " + kScenes +
                              "\nscenes: [balls-1.nff, rings-1.nff]\nsizes: [24x24]\npes: [1, 2, 3, 4]\n");
  const std::string out = tmp / "out";
  const std::string cmd = sweep_cmd(tmp / "spec.yaml", out, "--jobs 1 --no-plots");
  // A session of its own: the sweep is its leader, so its process group id is its pid.
  const std::string pid_file = tmp / "sweep.pid";
  ASSERT_EQ(std::system(("setsid sh -c 'echo $$ > " + pid_file + "; exec " + cmd + " > " + (tmp / "first.log") +
                         " 2>&1' </dev/null &")
                            .c_str()),
            0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  int pgid = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (!pgid) {
      const std::string p = slurp(pid_file);
      if (!p.empty() && p.back() == '\n') pgid = std::stoi(p);
    }
    if (pgid && data_rows(out + "/results.csv") >= 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_GT(pgid, 0);
  ASSERT_EQ(kill(-pgid, SIGKILL), 0);
  // GNU parallel gives each job its own process group; the jobs notice their parent died and stop.
  const auto gone_by = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (!live_in_session(pgid).empty() && std::chrono::steady_clock::now() < gone_by)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_TRUE(live_in_session(pgid).empty()) << "processes left running after the kill";

  const Csv before = read_csv(out + "/results.csv");
  ASSERT_GE(before.rows.size(), 2u) << slurp(tmp / "first.log");
  ASSERT_LT(before.rows.size(), 8u) << "the sweep finished before it could be interrupted";
  std::map<std::string, fs::file_time_type> finished;
  for (const auto& row : before.rows) {
    EXPECT_EQ(row.at("status"), "ok");
    finished[row.at("run_id")] = fs::last_write_time(out + "/runs/" + row.at("run_id") + ".json");
  }

  const Proc resumed = sh(cmd, tmp);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
  EXPECT_NE(resumed.out.find(std::to_string(before.rows.size()) + " already done"), std::string::npos) << resumed.out;
  EXPECT_NE(resumed.out.find("8 rows: 8 ok, 0 missing"), std::string::npos) << resumed.out;

  const Csv after = read_csv(out + "/results.csv");
  EXPECT_EQ(after.header, kColumns);
  ASSERT_EQ(after.rows.size(), 8u);
  std::map<std::string, int> times;
  std::set<std::pair<std::string, std::string>> configs;
  for (const auto& row : after.rows) {
    ++times[row.at("run_id")];
    configs.insert({row.at("scene"), row.at("pes")});
    EXPECT_EQ(row.at("status"), "ok") << row.at("run_id") << ": " << row.at("error");
    EXPECT_TRUE(is_number(row.at("cycles")));
  }
  EXPECT_EQ(times.size(), 8u);
  for (const auto& [id, n] : times) EXPECT_EQ(n, 1) << id;
  EXPECT_EQ(configs.size(), 8u);
  for (const auto& [id, when] : finished)
    EXPECT_EQ(fs::last_write_time(out + "/runs/" + id + ".json"), when) << id << " was run again";
}

// Failing configurations are rows too: rejected by rtm, a missing scene, a deadlock.
TEST(Sweep, FailedRunsAreRecordedWithTheirErrorMessage) {
  Tmp tmp;
  spit(tmp / "spec.yaml", "name: failing\nscene_dir: " + kScenes +
                              "\nscenes: [balls-1.nff, no-such-scene.nff]\nsizes: [16x16]\n"
                              "set:\n"
                              "  search_fifo_depth: [1]\n  intersect_fifo_depth: [1]\n  feedback_fifo_depth: [1]\n"
                              "  shade_fifo_depth: [1]\n  root_fifo_depth: [1]\n"
                              "  flow_control: [credits, none]\n  loop_credits: [0, 999]\n");
  const std::string out = tmp / "out";
  const Proc r = sh(sweep_cmd(tmp / "spec.yaml", out, "--jobs 2 --no-plots"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;  // every run has its row
  EXPECT_NE(r.out.find("8 rows: 1 ok, 1 deadlock, 6 failed, 0 missing"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("no-such-scene.nff"), std::string::npos) << r.err;  // warned up front

  const Csv csv = read_csv(out + "/results.csv");
  std::vector<std::string> want = kColumns;
  want.insert(want.begin() + 11, {"search_fifo_depth", "intersect_fifo_depth", "feedback_fifo_depth",
                                  "shade_fifo_depth", "root_fifo_depth", "flow_control", "loop_credits"});
  EXPECT_EQ(csv.header, want);
  ASSERT_EQ(csv.rows.size(), 8u);
  int ok = 0, deadlock = 0, rejected = 0, missing = 0;
  for (const auto& row : csv.rows) {
    const std::string& status = row.at("status");
    const std::string& error = row.at("error");
    const std::string where = row.at("run_id") + " " + row.at("flow_control") + " " + row.at("loop_credits");
    EXPECT_EQ(row.at("search_fifo_depth"), "1");
    if (status != "ok") {
      EXPECT_EQ(row.at("cycles"), "") << where;
      EXPECT_FALSE(fs::exists(out + "/runs/" + row.at("run_id") + ".json")) << where;
      // The message is rtm's own, also in the run's stderr.
      EXPECT_NE(slurp(out + "/runs/" + row.at("run_id") + ".err").find(error), std::string::npos) << where;
    }
    if (row.at("scene") == "no-such-scene") {
      ++missing;
      EXPECT_EQ(status, "failed") << where;
      EXPECT_EQ(row.at("exit_code"), "1") << where;
      EXPECT_NE(error.find("cannot read scene file"), std::string::npos) << where << ": " << error;
    } else if (row.at("loop_credits") == "999") {
      ++rejected;
      EXPECT_EQ(status, "failed") << where;
      EXPECT_EQ(row.at("exit_code"), "2") << where;
      EXPECT_NE(error.find("loop_credits"), std::string::npos) << where << ": " << error;
    } else if (row.at("flow_control") == "none") {
      ++deadlock;
      EXPECT_EQ(status, "deadlock") << where;
      EXPECT_EQ(row.at("exit_code"), "3") << where;
      EXPECT_NE(error.find("deadlock"), std::string::npos) << where << ": " << error;
    } else {
      ++ok;
      EXPECT_EQ(status, "ok") << where << ": " << error;
      EXPECT_TRUE(is_number(row.at("cycles"))) << where;
    }
  }
  EXPECT_EQ(ok, 1);
  EXPECT_EQ(deadlock, 1);
  EXPECT_EQ(rejected, 2);
  EXPECT_EQ(missing, 4);

  // Rerunning doesn't retry them (they are results); --retry-failed does, and they fail the same way.
  const Proc again = sh(sweep_cmd(tmp / "spec.yaml", out, "--jobs 2 --no-plots"), tmp);
  EXPECT_EQ(again.exit_code, 0);
  EXPECT_EQ(again.out.find("[1/8]"), std::string::npos) << again.out;
  const Proc retry = sh(sweep_cmd(tmp / "spec.yaml", out, "--jobs 2 --no-plots --retry-failed"), tmp);
  EXPECT_EQ(retry.exit_code, 0) << retry.err;
  EXPECT_NE(retry.out.find("retrying 7 run(s)"), std::string::npos) << retry.out;
  EXPECT_NE(retry.out.find("8 rows: 1 ok, 1 deadlock, 6 failed, 0 missing"), std::string::npos) << retry.out;
  EXPECT_EQ(read_csv(out + "/results.csv").rows.size(), 8u);
}

// Variants: named machines in one sweep, one `variant` column, each with its own settings.
TEST(Sweep, VariantsAreWholeMachinesComparedSideBySide) {
  Tmp tmp;
  spit(tmp / "spec.yaml", "name: variants\nscene_dir: " + kScenes +
                              "\nscenes: [balls-1.nff]\nsizes: [16x16]\npes: [1, 2]\nset:\n  search_units: [2]\n"
                              "variants:\n  paper: {}\n"
                              "  improved: {ray_generation: pe, broadcast: true, gather: as_finished}\n");
  const std::string out = tmp / "out";
  const Proc r = sh(sweep_cmd(tmp / "spec.yaml", out, "--jobs 2 --no-plots"), tmp);
  ASSERT_EQ(r.exit_code, 2) << "search_units is an axis, not a set key: " << r.out << r.err;
  spit(tmp / "spec.yaml", "name: variants\nscene_dir: " + kScenes +
                              "\nscenes: [balls-1.nff]\nsizes: [16x16]\npes: [1, 2]\nset:\n  loop_credits: [0]\n"
                              "variants:\n  paper: {}\n"
                              "  improved: {ray_generation: pe, broadcast: true, gather: as_finished, partition: pixels}\n");
  const Proc ok = sh(sweep_cmd(tmp / "spec.yaml", out, "--jobs 2"), tmp);
  ASSERT_EQ(ok.exit_code, 0) << ok.out << ok.err;
  const Csv csv = read_csv(out + "/results.csv");
  std::vector<std::string> want = kColumns;
  want.insert(want.begin() + 11, {"variant", "loop_credits"});
  EXPECT_EQ(csv.header, want);
  ASSERT_EQ(csv.rows.size(), 4u);
  std::map<std::string, int> per_variant;
  for (const auto& row : csv.rows) {
    ASSERT_EQ(row.at("status"), "ok") << row.at("error");
    ++per_variant[row.at("variant")];
    const json stats = json::parse(slurp(out + "/runs/" + row.at("run_id") + ".json"));
    const bool improved = row.at("variant") == "improved";
    EXPECT_EQ(stats["config"]["ray_generation"], improved ? "pe" : "host") << row.at("run_id");
    EXPECT_EQ(stats["config"]["gather"], improved ? "as_finished" : "after_all") << row.at("run_id");
    // A variant may fix a top-level axis: its runs use its value instead of the axis's.
    EXPECT_EQ(row.at("partition"), improved ? "pixels" : "scanlines") << row.at("run_id");
  }
  EXPECT_EQ(per_variant, (std::map<std::string, int>{{"improved", 2}, {"paper", 2}}));
  for (const std::string& png : kPlots) expect_png(out + "/plots/" + png);
}

// A bad spec is a usage error, before anything runs.
TEST(Sweep, ABadSpecIsRejectedUpFront) {
  Tmp tmp;
  const std::string out = tmp / "out";
  spit(tmp / "typo.yaml", "scenes: [" + kScenes + "/balls-1.nff]\npe: [1, 2]\n");
  Proc r = sh(sweep_cmd(tmp / "typo.yaml", out), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown key(s) pe"), std::string::npos) << r.err;
  spit(tmp / "key.yaml", "scenes: [" + kScenes + "/balls-1.nff]\nset: {search_fifo_dept: [4]}\n");
  r = sh(sweep_cmd(tmp / "key.yaml", out), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("search_fifo_dept: unknown machine configuration key"), std::string::npos) << r.err;
  spit(tmp / "size.yaml", "scenes: [" + kScenes + "/balls-1.nff]\nsizes: [32by32]\n");
  r = sh(sweep_cmd(tmp / "size.yaml", out), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not WxH"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  // --dry-run lists the rtm command of every run and runs none.
  spit(tmp / "dry.yaml", "scenes: [" + kScenes + "/balls-1.nff]\nsizes: [16x16]\npes: [1, 8]\n"
                         "set: {search_fifo_depth: [4, 8]}\n");
  r = sh(sweep_cmd(tmp / "dry.yaml", out, "--dry-run"), tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("4 runs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--pes 8 --set search_fifo_depth=4"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
}

// plot-sweep on a hand-written CSV: all six plots, failed rows left out, no 1-PE run noted.
TEST(Sweep, PlotSweepWritesItsPngFiles) {
  Tmp tmp;
  std::ostringstream csv;
  for (size_t i = 0; i < kColumns.size(); ++i) csv << (i ? "," : "") << kColumns[i];
  csv << "\n";
  int n = 0;
  auto row = [&](const std::string& scene, const std::string& partition, int pes, const std::string& status) {
    std::map<std::string, std::string> v;
    v["run_id"] = scene + "-" + partition + "-p" + std::to_string(pes);
    v["status"] = status;
    v["scene"] = scene;
    v["width"] = v["height"] = "64";
    v["pes"] = std::to_string(pes);
    v["partition"] = partition;
    v["search_units"] = "4";
    v["timing"] = "fast";
    v["precision"] = "fp32";
    if (status == "ok") {
      const double work = 1e6 / pes * (partition == "blocks" ? 1.1 : 1.0), host = 2e5, transfer = 1e4 * pes;
      v["cycles"] = std::to_string(int64_t(host + transfer + work + 5000));
      v["host_preprocess_cycles"] = std::to_string(int64_t(host));
      v["transfer_cycles"] = std::to_string(int64_t(transfer));
      v["pe_cycles"] = std::to_string(int64_t(work));
      v["gather_cycles"] = "5000";
      v["load_imbalance"] = std::to_string(1.0 + 0.02 * pes);
      for (const char* s : {"front_buffer", "search", "mac", "root", "shading"}) {
        v[std::string("util_") + s] = std::to_string(0.5 / (1 + 0.1 * pes));
        v[std::string("pe_util_") + s] = std::to_string(0.6 / (1 + 0.05 * pes));
      }
      v["pe_util_credit_stall"] = "0.3";
    } else {
      v["error"] = "rtm: deadlock: the simulation stopped, with rays outstanding";
    }
    for (size_t i = 0; i < kColumns.size(); ++i) {
      const std::string& cell = v[kColumns[i]];
      csv << (i ? "," : "") << (cell.find(',') != std::string::npos ? "\"" + cell + "\"" : cell);
    }
    csv << "\n";
    n += status == "ok";
  };
  for (int pes : {1, 2, 4, 8}) row("balls-4", "scanlines", pes, "ok");
  for (int pes : {1, 2, 4, 8}) row("balls-4", "blocks", pes, "ok");
  for (int pes : {2, 4, 8}) row("rings-7", "scanlines", pes, "ok");  // no 1-PE run
  row("rings-7", "scanlines", 1, "deadlock");
  row("rings-7", "blocks", 16, "failed");
  spit(tmp / "results.csv", csv.str());

  const Proc r = sh(kPlot + " " + (tmp / "results.csv") + " " + (tmp / "plots"), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find(std::to_string(n) + " runs in 3 configurations (2 failed rows left out)"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("relative to the smallest PE count"), std::string::npos) << r.out;
  for (const auto& p : kPlots) {
    expect_png(tmp / ("plots/" + p));
    EXPECT_NE(r.out.find(tmp / ("plots/" + p)), std::string::npos) << p;
  }
  // The scaling table: a header, a rule and one line per successful run, efficiency from the
  // configuration's first run (balls-4 scanlines on 2 PEs: 1,215,000 / (2 · 725,000) = 0.84).
  const std::string table = slurp(tmp / "plots/scaling.md");
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 2 + n) << table;
  EXPECT_NE(table.find("| balls-4 scanlines | 2 | 725,000 | 1.7 | 0.84 |"), std::string::npos) << table;

  // Nothing to plot: an error, no files.
  spit(tmp / "failed.csv", csv.str().substr(0, csv.str().find('\n') + 1));
  const Proc none = sh(kPlot + " " + (tmp / "failed.csv") + " " + (tmp / "none"), tmp);
  EXPECT_NE(none.exit_code, 0);
  EXPECT_NE(none.err.find("no successful runs"), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(tmp / "none/cycles.png"));
}
