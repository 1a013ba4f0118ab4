"""scripts/stress-deadlock: random configurations rendered with GNU parallel, every one that
deadlocks, fails or strays from the reference reported with the seed that gives it again."""

import importlib.machinery
import importlib.util
import os
import re
import subprocess


SCRIPTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRESS = os.path.join(SCRIPTS, "stress-deadlock")


def load_script():
    """scripts/stress-deadlock as a module (its name has no .py)."""
    loader = importlib.machinery.SourceFileLoader("stress_deadlock", STRESS)
    module = importlib.util.module_from_spec(importlib.util.spec_from_loader("stress_deadlock", loader))
    loader.exec_module(module)
    return module


def stress(*args, env=None):
    return subprocess.run([STRESS, *map(str, args)], capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          timeout=300, env=dict(os.environ, **(env or {})))


def test_random_configurations_finish_and_each_seed_gives_the_same_machine(rtm):
    r = stress(3, 11, "--jobs", 2, "--rtm", rtm)
    assert r.returncode == 0, r.stdout + r.stderr
    assert re.search(r"^stress-deadlock: 3 configurations of seed 11 in \d+ s: 3 ok; slowest", r.stdout, re.M), r.stdout
    one = stress("--one", "11:2", "--rtm", rtm)
    again = stress("--one", "11:2", "--rtm", rtm)
    assert one.returncode == 0 and one.stdout.startswith("ok 11:2 "), one.stdout + one.stderr
    command = one.stdout.split(": ", 1)[1]
    assert command == again.stdout.split(": ", 1)[1]
    assert "--set arbitration=" in command and "--timing " in command and "--set loop_credits=" in command


def test_a_deadlock_a_failure_and_a_mismatch_are_reported_with_their_seeds(tmp_path):
    # A stand-in for rtm: configuration 0 of seed 5 deadlocks, 1 fails, 2 strays from the
    # reference, 3 renders; each is told apart by the scene drawn for it.
    script = load_script()
    scenes = {i: script.configuration("5", i)[0] for i in range(4)}
    assert len(set(scenes.values())) == 4, "pick another seed: two configurations draw one scene"
    fake = tmp_path / "rtm"
    fake.write_text(f"""#!/usr/bin/python3
import json, sys
args = sys.argv[1:]
scene = args[1]
if scene == {scenes[0]!r}:
    print("rtm: deadlock: the simulation stopped with rays outstanding", file=sys.stderr); sys.exit(3)
if scene == {scenes[1]!r}:
    print("rtm: something broke", file=sys.stderr); sys.exit(1)
off = 9 if scene == {scenes[2]!r} else 0
stats = {{"error": {{"pixels_over_1_255": off}}, "reference": {{"rays_match": off == 0}}, "rays": {{}}}}
json.dump(stats, open(args[args.index("--stats") + 1], "w"))
""")
    fake.chmod(0o755)
    r = stress(4, 5, "--jobs", 2, "--rtm", fake)
    assert r.returncode == 1, r.stdout + r.stderr
    assert "4 configurations of seed 5" in r.stdout and "1 DEADLOCK, 1 FAILED, 1 MISMATCH, 1 ok" in r.stdout, r.stdout
    for verdict, index in (("DEADLOCK", 0), ("FAILED", 1), ("MISMATCH", 2)):
        assert re.search(rf"^{verdict} 5:{index}: \S+ render {re.escape(scenes[index])} ", r.stdout, re.M), r.stdout
        assert f"reproduce: scripts/stress-deadlock --one 5:{index}" in r.stdout
    assert "the simulation stopped with rays outstanding" in r.stdout
    assert "exit 1: rtm: something broke" in r.stdout
    assert "9 pixels off the reference" in r.stdout
    one = stress("--one", "5:0", "--rtm", fake)
    assert one.returncode == 1 and one.stdout.startswith("DEADLOCK 5:0 "), one.stdout


def test_bad_command_lines_exit_2():
    assert stress().returncode == 2
    r = stress("--one", "nocolon")
    assert r.returncode == 2 and "expected SEED:I" in r.stderr
