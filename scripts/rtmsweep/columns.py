"""The columns of a sweep's results.csv, in order. Everything that writes, reads or plots the CSV
takes its column lists from here.

    HEAD_COLUMNS, then the spec's `set` keys (with `variant` first), then METRIC_COLUMNS
"""

# The run and its configuration.
CONFIG_COLUMNS = ["scene", "width", "height", "pes", "partition", "search_units", "timing", "precision"]
HEAD_COLUMNS = ["run_id", "status", "error"] + CONFIG_COLUMNS

# rtm's figures of a finished run: the stats JSON's `summary` object holds exactly these keys
# (tb/stats_json.cpp, summary_json; docs/stats.schema.json documents each), and a row copies them as
# they are.
SUMMARY_COLUMNS = [
    "cycles", "wall_seconds",
    "error_rmse", "error_psnr_db", "error_max_abs", "error_pixels_over_1_255", "error_primary_ids_differing",
    "rays_primary", "rays_shadow", "rays_reflected", "rays_transmitted",
    "util_front_buffer", "util_search", "util_mac", "util_root", "util_shading",
    "load_imbalance",
    "host_preprocess_cycles", "transfer_cycles", "pe_cycles", "gather_cycles", "link_busy_cycles",
    "bottleneck", "mac_bound_cycles", "cycles_over_mac_bound",
    "sim_time_ns", "voxel_steps", "intersection_tests", "mac_products", "mac_busy_cycles",
    "pe_util_front_buffer", "pe_util_search", "pe_util_mac", "pe_util_root", "pe_util_shading",
    "pe_util_credit_stall",
    "pe_issue_front_buffer", "pe_issue_search", "pe_issue_mac", "pe_issue_root", "pe_issue_shading",
    "pe_starved_front_buffer", "pe_starved_search", "pe_starved_mac", "pe_starved_root", "pe_starved_shading",
    "area_mm2", "energy_j", "power_w", "frames_per_s_per_mm2", "frames_per_j", "energy_delay",
    "energy_front_buffer_j", "energy_shading_j", "energy_search_j", "energy_mac_j", "energy_root_j",
    "energy_local_memory_j", "energy_link_j", "energy_leakage_j",
    # A frame's time: with several frames (the key frames) the steady state's; else cycles.
    "frame_cycles",
]
# The sweep's own: how rtm exited, where it ran, which file it read.
RUN_COLUMNS = ["exit_code", "host", "scene_file"]
# Which build made the figures, from the stats JSON's `build`: its commit, with "-modified" when
# its tracked files differed from it (`rtm --version`).
BUILD_COLUMNS = ["commit"]
METRIC_COLUMNS = SUMMARY_COLUMNS + RUN_COLUMNS + BUILD_COLUMNS
# The frame's phases are cycle counts that rtm's summary gives as floats; the CSV writes a whole
# number as an integer there, as it always has.
INTEGER_COLUMNS = ["host_preprocess_cycles", "transfer_cycles", "pe_cycles", "gather_cycles"]


def header(set_keys):
    """The CSV header of a sweep whose spec sets these keys (`variant` first when it has variants)."""
    return HEAD_COLUMNS + list(set_keys) + METRIC_COLUMNS
