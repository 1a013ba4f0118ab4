"""Random machine configurations for the scripts that try many (scripts/engine-vs-modules,
scripts/stress-deadlock): every timing parameter, FIFO depth and unit count the PE loop has,
drawn so that the loop cannot deadlock by design (docs/machine.md, "Front buffer": FIFOs no
shallower than the search FIFO, loop credits within its depth). A seeded random.Random gives the
same configurations on every run.
"""


def random_config(rng, scenes):
    """`rtm render` arguments: one of SCENES (paths), a frame of 8..40 pixels a side, and a
    random machine (credits flow control, the ranked order; the caller adds other axes)."""
    d = rng.randint(1, 6)
    args = [rng.choice(scenes), "--size", f"{rng.randint(8, 40)}x{rng.randint(8, 40)}", "--pes", str(rng.randint(1, 9)),
            "--search-units", str(rng.randint(1, 8)), "--partition", rng.choice(["scanlines", "blocks", "strips", "pixels"]),
            "--precision", rng.choice(["fp32", "fp64"]), "--mac-schedule", rng.choice(["sparse", "full"])]
    sets = {"search_fifo_depth": d, "intersect_fifo_depth": rng.randint(d, 8), "root_fifo_depth": rng.randint(d, 8),
            "shade_fifo_depth": rng.randint(d, 8), "feedback_fifo_depth": rng.randint(1, 6),
            "front_buffer_capacity": rng.randint(1, 70), "loop_credits": rng.randint(0, d),
            "fb_dispatch_cycles": rng.randint(1, 4), "dda_step_cycles": rng.randint(1, 4),
            "memory_latency": rng.randint(1, 4), "memory_bytes_per_cycle": rng.choice([4, 8, 16]), "shade_cycles": rng.randint(1, 20),
            "spawn_cycles": rng.randint(0, 6), "accumulate_cycles": rng.randint(1, 4), "root_latency": rng.randint(1, 14),
            "clip_cycles": rng.randint(0, 5), "sort_cycles": rng.randint(0, 2), "mul_latency": rng.randint(1, 3),
            "add_latency": rng.randint(1, 2), "memory_interleave_bytes": rng.choice([4, 8, 16, 32]),
            "ray_block": rng.choice([0, 0, 1, 7, 50]), "ray_generation": rng.choice(["host", "pe"]),
            "broadcast": rng.choice(["true", "false"]), "gather": rng.choice(["after_all", "as_finished"]),
            "search_walk": rng.choice(["per_voxel", "until_occupied"]), "clock_ns": rng.choice([10, 7, 3.3]),
            "host_clock_ns": rng.choice([10, 4.1]), "leave_out": rng.choice(["true", "false"]),
            "intersection_units": rng.choice([1, 1, 2, 3]),
            "dispatch_interval": rng.choice([0, 1, 2]), "search_interval": rng.choice([0, 1, 1, 3]),
            "mac_streaming": rng.choice(["true", "false"]), "root_interval": rng.choice([0, 1, 2]),
            "shade_interval": rng.choice([0, 1, 4])}
    # The interconnect, drawn after the rest (whose draws stay what they were); a broadcast on a
    # star needs a host port per PE.
    sets.update({"link_topology": rng.choice(["serial", "bus", "star", "tree"]), "host_ports": rng.randint(1, 4),
                 "tree_fanout": rng.randint(1, 3)})
    # The local memory (docs/memory.md), drawn after the interconnect.
    sets.update({"memory_ports": rng.choice([0, 1, 1, 2, 3]), "memory_banks": rng.choice([0, 1, 2, 4, 8]),
                 "memory_arbitration": rng.choice(["round_robin", "fixed_priority", "fcfs"]),
                 "mac_ram_primitives": rng.choice([0, 1, 2, 4, 16]), "voxel_cache_bytes": rng.choice([0, 0, 64, 1024])})
    # Each unit's arithmetic and the hit refinement (docs/numerics.md), drawn after the memory.
    sets.update({"intersection_precision": rng.choice(["precision", "fp32", "fp64"]),
                 "dda_precision": rng.choice(["precision", "fp32", "fp64"]),
                 "shading_precision": rng.choice(["precision", "fp32", "fp64"]),
                 "hit_refine": rng.choice(["none", "newton"]), "refine_cycles": rng.randint(0, 10)})
    # The mechanisms of a machine that scales (docs/machine.md), drawn after the arithmetic.
    sets.update({"voxelisation": rng.choice(["host", "pe"]),
                 "tree_forwarding": rng.choice(["store_and_forward", "cut_through"]),
                 "scene_block": rng.choice([0, 0, 1, 3, 50]), "gather_block": rng.randint(1, 40)})
    if rng.random() < 0.3:
        sets["gather"] = "streamed"
    # A dynamic partition (tiles on demand): a tile's rays go as the PE asks, so no ray_block.
    if rng.randrange(3) == 0:
        args[args.index("--partition") + 1] = "dynamic"
        sets.update({"tile": rng.randint(1, 12), "ray_block": 0})
    # Several frames through the pipelined host, on a static partition with each frame's rays at
    # once (drawn last, so the draws before stay what they were).
    elif rng.randrange(3) == 0:
        sets.update({"frames": rng.randint(2, 4), "ray_block": 0})
    if sets["link_topology"] == "star" and sets["broadcast"] == "true":
        sets["host_ports"] = max(sets["host_ports"], int(args[args.index("--pes") + 1]))
    for k, v in sets.items():
        args += ["--set", f"{k}={v}"]
    return args
