"""A sweep as a Slurm job array (docs/sweeps.md, "Slurm"), on a one-node Slurm of the test's own:
scripts/sweep.sbatch submitted with the section's sbatch commands, every row arriving exactly
once; then a task cancelled while it runs, the same array submitted again, every row exactly once
again, and the plots job after it.

The cluster is Debian's slurm-wlm and munge (scripts/setup installs them), started by the test
as root, in the foreground, with a slurm.conf, a munge key and state, spool and log folders in
the test's folder, the node being this machine as `slurmd -C` describes it (its real CPUs),
ports of its own, no systemd and no cgroups (proctrack/linuxproc, task/none). The daemons are
stopped when the tests end, and get SIGTERM if the test process dies first.

Under ctest (RTM_REQUIRE_SLURM=1, set by CMakeLists.txt) not being root or missing a package
fails the tests; run by hand elsewhere they are skipped.
"""

import os
import shutil
import signal
import socket
import subprocess
import time

import pytest

from support import ROOT, env, read_csv, row_files, write_spec
from rtmsweep import run, spec

SBATCH_SCRIPT = "scripts/sweep.sbatch"  # submitted from the checkout, as the docs say
SBIN = "/usr/sbin:/usr/bin:/sbin:/bin"
PROGRAMS = {"munged": "munge", "mungekey": "munge", "slurmctld": "slurmctld", "slurmd": "slurmd",
            "sbatch": "slurm-client", "squeue": "slurm-client", "scancel": "slurm-client", "sinfo": "slurm-client"}
FINAL_STATES = {"COMPLETED", "CANCELLED", "FAILED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY", "PREEMPTED",
                "BOOT_FAIL", "DEADLINE"}
TASKS = 3
# Each run long enough (a few tenths of a second) that a shard is still going when it is cancelled.
SPEC = "name: slurm\nscenes: [balls-1.nff, rings-1.nff]\nsizes: [48x48]\npes: [1, 2, 3, 4]\n"


def missing(reason):
    if os.environ.get("RTM_REQUIRE_SLURM"):
        pytest.fail(f"{reason} (scripts/setup, run as root, installs slurm-wlm and munge)", pytrace=False)
    pytest.skip(reason)


def free_ports(n):
    sockets = [socket.socket() for _ in range(n)]
    try:
        for s in sockets:
            s.bind(("127.0.0.1", 0))
        return [s.getsockname()[1] for s in sockets]
    finally:
        for s in sockets:
            s.close()


class Slurm:
    """munged, slurmctld and slurmd for this test, and its clients' environment."""

    def __init__(self, folder):
        self.folder = folder
        self.procs = []
        self.conf = folder / "slurm.conf"
        self.env = dict(env(), SLURM_CONF=str(self.conf))
        self.env["PATH"] = self.env.get("PATH", "") + ":" + SBIN  # the daemons and mungekey are in sbin

    def start_all(self):
        folder = self.folder
        for sub in ("munge", "state", "spool", "logs"):
            (folder / sub).mkdir(mode=0o700, parents=True)
        os.chmod(folder, 0o700)
        key, sock = folder / "munge" / "munge.key", folder / "munge" / "munge.socket"
        self.check(["mungekey", "--create", f"--keyfile={key}"])
        self.start("munged", ["munged", "--foreground", "--force", f"--key-file={key}", f"--socket={sock}",
                              f"--pid-file={folder}/munge/munged.pid", f"--log-file={folder}/logs/munged.log",
                              f"--seed-file={folder}/munge/munged.seed"])
        self.wait_for(lambda: sock.exists(), "munged's socket", "munged")
        # This machine as slurmd sees it: CPUs, sockets, cores, threads and memory.
        node = self.check(["slurmd", "-C"]).splitlines()[0].split()
        hardware = " ".join(f for f in node if not f.startswith("NodeName="))
        self.cpus = int(next(f for f in node if f.startswith("CPUs=")).split("=")[1])
        ctld_port, d_port = free_ports(2)
        self.conf.write_text(
            "ClusterName=rtm-test\nSlurmctldHost=localhost(127.0.0.1)\n"
            f"SlurmctldPort={ctld_port}\nSlurmdPort={d_port}\nSlurmUser=root\nSlurmdUser=root\n"
            f"AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket={sock}\n"
            f"StateSaveLocation={folder}/state\nSlurmdSpoolDir={folder}/spool\n"
            f"SlurmctldPidFile={folder}/slurmctld.pid\nSlurmdPidFile={folder}/slurmd.pid\n"
            f"SlurmctldLogFile={folder}/logs/slurmctld.log\nSlurmdLogFile={folder}/logs/slurmd.log\n"
            # No systemd and no cgroups: processes tracked by their parents, tasks not confined.
            "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\nJobAcctGatherType=jobacct_gather/none\n"
            "AccountingStorageType=accounting_storage/none\nSwitchType=switch/none\nMpiDefault=none\n"
            "MailProg=/bin/true\nReturnToService=2\nKillWait=5\nMinJobAge=600\n"
            "SchedulerType=sched/builtin\nSelectType=select/cons_tres\nSelectTypeParameters=CR_CPU\n"
            f"NodeName=localhost NodeAddr=127.0.0.1 {hardware} State=UNKNOWN\n"
            "PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n")
        self.start("slurmctld", ["slurmctld", "-D", "-i", "-f", str(self.conf)])
        self.start("slurmd", ["slurmd", "-D", "-N", "localhost", "-f", str(self.conf)])
        self.wait_for(lambda: self.run(["sinfo", "-h", "-n", "localhost", "-o", "%T"]).stdout.strip() == "idle",
                      "the node to be idle", "slurmctld", 60)

    def start(self, name, cmd):
        log = open(self.folder / "logs" / f"{name}.out", "w")
        # If the test process dies without its teardown, the daemons go with it.
        self.procs.append((name, subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                                  env=self.env,
                                                  preexec_fn=lambda: run._set_pdeathsig(signal.SIGTERM))))
        log.close()

    def logs(self, name):
        text = ""
        for path in sorted((self.folder / "logs").glob(f"{name}*")):
            text += f"--- {path.name}\n{path.read_text(errors='replace')[-3000:]}"
        return text

    def wait_for(self, ready, what, daemon, timeout=30):
        deadline = time.monotonic() + timeout
        while not ready():
            dead = [name for name, p in self.procs if p.poll() is not None]
            if dead or time.monotonic() > deadline:
                pytest.fail(f"waiting for {what}: " + (f"{dead[0]} exited" if dead else f"not after {timeout} s")
                            + "\n" + self.logs(dead[0] if dead else daemon), pytrace=False)
            time.sleep(0.2)

    def run(self, cmd, cwd=None, timeout=60, **more_env):
        return subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL, cwd=cwd,
                              env=dict(self.env, **more_env), timeout=timeout)

    def check(self, cmd, cwd=None, timeout=60, **more_env):
        r = self.run(cmd, cwd, timeout, **more_env)
        assert r.returncode == 0, f"{' '.join(map(str, cmd))}: exit {r.returncode}\n{r.stdout}{r.stderr}"
        return r.stdout

    def states(self, job):
        """Each task of array JOB and its state, e.g. {"7_0": "COMPLETED", ...}."""
        out = self.check(["squeue", "-h", "-t", "all", "-j", str(job), "-o", "%i %T"])
        return dict(line.split() for line in out.splitlines())

    def wait(self, job, timeout=180):
        """Waits until every task of JOB has ended; returns their states."""
        deadline = time.monotonic() + timeout
        while True:
            states = self.states(job)
            if states and set(states.values()) <= FINAL_STATES and not any("[" in t for t in states):
                return states
            assert time.monotonic() < deadline, f"job {job} still going after {timeout} s: {states}\n" + \
                self.logs("slurm")
            time.sleep(0.3)

    def stop(self):
        if any(p.poll() is None for name, p in self.procs if name == "slurmctld"):
            # This cluster's jobs (SLURM_CONF names it), ended before their slurmd is.
            self.run(["scancel", "--user", "root"], timeout=30)
            deadline = time.monotonic() + 30
            while self.run(["squeue", "-h"], timeout=30).stdout.strip() and time.monotonic() < deadline:
                time.sleep(0.3)
        for _, p in reversed(self.procs):
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait(timeout=20)


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    if os.geteuid() != 0:
        missing("a Slurm of the test's own needs root (its slurmd runs jobs as their users)")
    absent = sorted({f"{program} ({package})" for program, package in PROGRAMS.items()
                     if not shutil.which(program, path=SBIN)})
    if absent:
        missing(f"not installed: {', '.join(absent)}")
    cluster = Slurm(tmp_path_factory.mktemp("slurm"))
    try:
        cluster.start_all()
        yield cluster
    finally:
        cluster.stop()


def submit(slurm, rtm, spec_path, out, cpus_per_task):
    """The docs' submission: the array, each task a shard over CPUS_PER_TASK CPUs (sbatch passes
    the environment on: the tasks' rtm is RTM_BINARY, their reference cache one for all)."""
    os.makedirs(out, exist_ok=True)
    job = slurm.check(["sbatch", "--parsable", f"--array=0-{TASKS - 1}", f"--cpus-per-task={cpus_per_task}",
                       f"--output={out}/slurm-%A_%a.log", SBATCH_SCRIPT, str(spec_path), str(out)], cwd=ROOT,
                      RTM_BINARY=rtm, RTM_CACHE_DIR=f"{out}/cache")
    return job.strip().split(";")[0]


def task_logs(out):
    return "".join(f"--- {p.name}\n{p.read_text(errors='replace')}" for p in sorted(out.glob("slurm-*.log")))


def check_every_row_once(out, ids):
    assert row_files(out) == sorted(f"{i}.row" for i in ids), task_logs(out)
    head, rows = read_csv(out / "results.csv")
    assert [r["run_id"] for r in rows] == ids, task_logs(out)  # each once, in the spec's order
    assert all(r["status"] == "ok" for r in rows), rows


@pytest.fixture
def cpus_per_task(slurm):
    """Two tasks at once on this node (one on a one-CPU node), whatever its size."""
    return max(1, slurm.cpus // 2)


def test_every_row_of_the_array_arrives_once(slurm, cpus_per_task, rtm, tmp_path):
    spec_path = write_spec(tmp_path / "slurm.yaml", SPEC)
    ids = [j["id"] for j in spec.load(spec_path).jobs()]
    out = tmp_path / "out"
    job = submit(slurm, rtm, spec_path, out, cpus_per_task)
    states = slurm.wait(job)
    assert states == {f"{job}_{i}": "COMPLETED" for i in range(TASKS)}, task_logs(out)
    check_every_row_once(out, ids)
    logs = task_logs(out)
    for i in range(TASKS):  # each task ran its own shard
        assert f"sweep slurm (shard {i}/{TASKS}): {len(ids[i::TASKS])} runs" in logs, logs


def test_a_cancelled_task_is_finished_by_submitting_the_array_again(slurm, cpus_per_task, rtm, tmp_path):
    spec_path = write_spec(tmp_path / "slurm.yaml", SPEC)
    ids = [j["id"] for j in spec.load(spec_path).jobs()]
    out = tmp_path / "out"
    job = submit(slurm, rtm, spec_path, out, cpus_per_task)
    victim = f"{job}_1"
    deadline = time.monotonic() + 120
    while (states := slurm.states(job)).get(victim) != "RUNNING":
        # One query a pass: a second one could see the task start after the first saw it pending.
        assert time.monotonic() < deadline and states.get(victim) in (None, "PENDING"), \
            f"{victim} did not run: {states}\n{task_logs(out)}"
        time.sleep(0.1)
    slurm.check(["scancel", victim])
    states = slurm.wait(job)
    assert states[victim] == "CANCELLED", states
    assert all(s == "COMPLETED" for t, s in states.items() if t != victim), (states, task_logs(out))
    done = {name: (out / "runs" / name).read_bytes() for name in row_files(out)}
    assert set(done) <= {f"{i}.row" for i in ids}
    lost = [i for i in ids[1::TASKS] if f"{i}.row" not in done]
    assert lost, f"{victim} finished its shard before it was cancelled; make the runs longer\n{task_logs(out)}"
    assert all(f"{i}.row" in done for i in ids[0::TASKS] + ids[2::TASKS]), task_logs(out)
    status = slurm.run(["scripts/sweep", str(spec_path), "--out", str(out), "--status"], cwd=ROOT, RTM_BINARY=rtm)
    assert status.returncode == 1 and f"{len(lost)} missing" in status.stdout, status.stdout + status.stderr

    again = submit(slurm, rtm, spec_path, out, cpus_per_task)
    assert slurm.wait(again) == {f"{again}_{i}": "COMPLETED" for i in range(TASKS)}, task_logs(out)
    check_every_row_once(out, ids)
    for name, data in done.items():  # the runs that had their rows were not run again
        assert (out / "runs" / name).read_bytes() == data, name

    # The docs' last step: the plots, once every task has ended.
    plots = slurm.run(["sbatch", "--parsable", "--wait", f"--dependency=afterany:{again}",
                       f"--output={out}/slurm-plots.log", "--wrap",
                       f"scripts/sweep {spec_path} --out {out} --status && "
                       f"scripts/plot-sweep {out}/results.csv {out}/plots"], cwd=ROOT, timeout=180, RTM_BINARY=rtm)
    assert plots.returncode == 0, plots.stdout + plots.stderr + task_logs(out)
    assert (out / "plots" / "cycles.png").is_file(), task_logs(out)
