"""Sweeps over several hosts (docs/sweeps.md, "Several hosts") through real SSH: an sshd of the
test's own on 127.0.0.1 and a free port, two sshlogin entries for it (two aliases in an ssh
config of the test's), GNU parallel --sshloginfile, with the shared folder and with
--no-shared-dir, each killed half-way and resumed; every row must appear exactly once.

The sshd is Debian's openssh-server (scripts/setup installs it), started by the test as whoever
runs it, not daemonised, with its own config file and a throwaway host key and user key in the
test's folder. As root it needs /run/sshd, its privilege-separation folder, which the system
service would create (the test creates it if missing); for --no-shared-dir the "hosts" then run
in a mount namespace of their own where an empty tmpfs hides the sweep's folder, so the rows can
only come back through GNU parallel's --transferfile and --return. As another user sshd can only
let that user in; then, and as a root that may not make a mount namespace, the hosts see the
sweep's folder: the --no-shared-dir case still runs every transfer through SSH and rsync, but
could not tell a missing --return, and says so in a warning.

Under ctest (RTM_REQUIRE_SSHD=1, set by CMakeLists.txt) a missing or failing sshd fails the
tests, naming the package; run by hand on a machine without it they are skipped.
"""

import getpass
import os
import shutil
import signal
import socket
import subprocess
import time
import warnings

import pytest

from support import SCENES, SWEEP, env, is_number, read_csv, row_files

SSHD = "/usr/sbin/sshd"
ROOT_USER = os.geteuid() == 0


def can_hide_folders():
    """Whether this process may give sshd a mount namespace of its own (root with CAP_SYS_ADMIN)."""
    try:
        return ROOT_USER and subprocess.run(["unshare", "--mount", "--propagation", "private", "true"],
                                            capture_output=True, timeout=30).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


SCENE_NAMES = ["balls-1.nff", "rings-1.nff"]
PES = [1, 2, 3, 4]
RUNS = len(SCENE_NAMES) * len(PES)


def missing(reason):
    if os.environ.get("RTM_REQUIRE_SSHD"):
        pytest.fail(f"{reason} (install openssh-server: scripts/setup does)", pytrace=False)
    pytest.skip(reason)


def sanitizer_options():
    """This environment's sanitizer options, as more SetEnv assignments."""
    return "".join(f" {k}={os.environ[k]}" for k in ("ASAN_OPTIONS", "UBSAN_OPTIONS", "TSAN_OPTIONS") if k in os.environ)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def keygen(path):
    subprocess.run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-C", "rtm-test", "-f", path], check=True)


class Sshd:
    """An sshd on 127.0.0.1 for this test, and an ssh config naming it host-a and host-b."""

    def __init__(self, folder, hidden=None):
        self.folder = folder
        folder.mkdir()
        keygen(folder / "host_key")
        keygen(folder / "user_key")
        shutil.copy(folder / "user_key.pub", folder / "authorized_keys")
        (folder / "known_hosts").write_text("rtm-test-sshd " + (folder / "host_key.pub").read_text())
        if ROOT_USER:
            os.makedirs("/run/sshd", mode=0o755, exist_ok=True)
        self.proc = None
        for _ in range(5):  # another process may take the free port before sshd binds it
            self.port = free_port()
            (folder / "sshd_config").write_text(
                f"ListenAddress 127.0.0.1\nPort {self.port}\nHostKey {folder}/host_key\n"
                f"AuthorizedKeysFile {folder}/authorized_keys\nPidFile none\nUsePAM no\n"
                # The test's folder is under /tmp, which StrictModes would refuse.
                "StrictModes no\nPasswordAuthentication no\nKbdInteractiveAuthentication no\n"
                "PermitRootLogin prohibit-password\n"
                # A host's own environment: its reference cache, no SystemC banner, and in a
                # sanitizer build the sanitizers' options (scripts/test --sanitize).
                f"SetEnv RTM_CACHE_DIR={folder}/cache SYSTEMC_DISABLE_COPYRIGHT_MESSAGE=1{sanitizer_options()}\n")
            cmd = [SSHD, "-D", "-e", "-f", str(folder / "sshd_config")]
            if hidden is not None:
                cmd = ["unshare", "--mount", "--propagation", "private", "--", "sh", "-c",
                       'mount -t tmpfs rtm-remote "$1" && shift && exec "$@"', "sh", str(hidden)] + cmd
            log = open(folder / "sshd.log", "w")
            self.proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
            log.close()
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline and self.proc.poll() is None and "Server listening" not in self.log():
                time.sleep(0.05)
            if "Server listening" in self.log():
                break
            self.stop()
            if "Address already in use" not in self.log():
                pytest.fail(f"sshd did not start: {' '.join(cmd)}\n{self.log()}", pytrace=False)
        else:
            pytest.fail(f"sshd found no free port:\n{self.log()}", pytrace=False)
        (folder / "ssh_config").write_text(
            f"Host host-a host-b\n  HostName 127.0.0.1\n  Port {self.port}\n  User {getpass.getuser()}\n"
            f"  IdentityFile {folder}/user_key\n  IdentitiesOnly yes\n  BatchMode yes\n"
            f"  HostKeyAlias rtm-test-sshd\n  UserKnownHostsFile {folder}/known_hosts\n"
            "  GlobalKnownHostsFile /dev/null\n  StrictHostKeyChecking yes\n"
            "Host host-b\n  Compression yes\n")  # the second "host" differs in an ssh option too
        self.hosts = ["host-a", "host-b"]
        self.logins = [f"ssh -F {folder}/ssh_config {h}" for h in self.hosts]
        self.sshloginfile = folder / "hosts"
        self.sshloginfile.write_text("# one job at a time on each\n" + "".join(f"1/{s}\n" for s in self.logins))

    def log(self):
        try:
            return (self.folder / "sshd.log").read_text()
        except FileNotFoundError:
            return ""

    def ssh(self, host, command):
        return subprocess.run(["ssh", "-F", str(self.folder / "ssh_config"), host, command], capture_output=True,
                              text=True, stdin=subprocess.DEVNULL, timeout=30)

    def stop(self):
        if self.proc and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


@pytest.fixture
def sshd(tmp_path):
    """Starts an Sshd: sshd(hidden=FOLDER) runs its sessions where FOLDER looks empty (root only)."""
    if not os.access(SSHD, os.X_OK):
        missing(f"no sshd at {SSHD}")
    if not shutil.which("rsync"):
        missing("no rsync")
    started = []

    def start(hidden=None):
        started.append(Sshd(tmp_path / f"sshd{len(started)}", hidden))
        return started[-1]

    yield start
    for s in started:
        s.stop()


def sweep_processes(out):
    """Processes (pids) of this sweep's runs still alive anywhere, local or over SSH."""
    pids = []
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/cmdline", "rb") as f:
                cmd = f.read().decode(errors="replace")
            with open(f"/proc/{name}/stat") as f:
                state = f.read().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if str(out) in cmd and state not in "ZX":
            pids.append(int(name))
    return pids


def kill_half_way_then_resume(rtm, spec, out, args, tmp_path):
    """Runs the sweep, SIGKILLs its process group once two runs have their row, checks nothing of it
    goes on running, resumes it with the same command; returns (rows of the killed run, the resumed
    sweep's output)."""
    command = [SWEEP, spec, "--out", out, "--rtm", rtm, "--no-plots"] + args
    with open(tmp_path / "first.log", "w") as log:
        first = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                 env=env(), start_new_session=True)
    deadline = time.monotonic() + 60
    while len(row_files(out)) < 2 and time.monotonic() < deadline and first.poll() is None:
        time.sleep(0.01)
    os.killpg(first.pid, signal.SIGKILL)
    first.wait()
    done = row_files(out)
    assert len(done) >= 2, (tmp_path / "first.log").read_text()
    assert len(done) < RUNS, "the sweep finished before it could be interrupted"
    # GNU parallel killed does not stop its jobs over SSH: their ssh clients, in process groups of
    # their own, live on, and a run already going on a host finishes; it must not hang. A job whose
    # connection is still being made has nothing here yet to wait for: the resumed sweep may start
    # its run again while it goes, and sweep-run's lock makes that one attempt (test_run.py).
    gone_by = time.monotonic() + 20
    while sweep_processes(out) and time.monotonic() < gone_by:
        time.sleep(0.1)
    assert not sweep_processes(out), "runs left going 20 s after the sweep was killed"

    resumed = subprocess.run(command, capture_output=True, text=True, stdin=subprocess.DEVNULL, env=env(),
                             timeout=120)
    assert resumed.returncode == 0, resumed.stdout + resumed.stderr
    assert f"{RUNS} rows: {RUNS} ok, 0 missing" in resumed.stdout, resumed.stdout
    return done, resumed.stdout


def check_every_row_once(out, logins):
    head, rows = read_csv(out / "results.csv")
    ids = [r["run_id"] for r in rows]
    assert len(ids) == RUNS and len(set(ids)) == RUNS, ids
    assert {(r["scene"], int(r["pes"])) for r in rows} == {(s[:-4], p) for s in SCENE_NAMES for p in PES}
    assert all(r["status"] == "ok" and is_number(r["cycles"]) for r in rows), rows
    assert sorted(row_files(out)) == sorted(i + ".row" for i in ids)
    assert not [n for n in os.listdir(out / "runs") if n.endswith(".remote")]
    # GNU parallel's job log names the sshlogin each job ran on: both hosts worked.
    with open(out / "joblog") as f:
        used = {line.split("\t")[1] for line in f.read().splitlines()[1:] if line}
    assert used == set(logins), used


def write_spec(path, scene_dir):
    path.write_text(f"name: hosts\nscene_dir: {scene_dir}\nscenes: [{', '.join(SCENE_NAMES)}]\n"
                    f"sizes: [8x8]\npes: [{', '.join(map(str, PES))}]\n")
    return path


def test_a_sweep_over_two_hosts_sharing_its_folder_is_killed_and_resumed(rtm, sshd, tmp_path):
    hosts = sshd()
    for host in hosts.hosts:
        r = hosts.ssh(host, "echo $RTM_CACHE_DIR")
        assert r.returncode == 0 and r.stdout.strip() == f"{hosts.folder}/cache", r.stderr + hosts.log()
    spec = write_spec(tmp_path / "spec.yaml", SCENES)
    out = tmp_path / "out"
    done, _ = kill_half_way_then_resume(rtm, spec, out, ["--sshloginfile", str(hosts.sshloginfile)], tmp_path)
    finished = {n[:-4]: os.stat(out / "runs" / (n[:-4] + ".json")).st_mtime_ns for n in done}
    check_every_row_once(out, hosts.logins)
    for rid, when in finished.items():
        assert os.stat(out / "runs" / f"{rid}.json").st_mtime_ns == when, f"{rid} was run again"
    # The runs ran through the hosts' sshd: their reference images are in the hosts' cache.
    assert os.listdir(hosts.folder / "cache")


def test_a_sweep_over_two_hosts_without_the_shared_folder_is_killed_and_resumed(rtm, sshd, tmp_path):
    shared = tmp_path / "here"  # what the hosts do not see (as root)
    scenes = shared / "scenes"
    scenes.mkdir(parents=True)
    for name in SCENE_NAMES:
        shutil.copy(os.path.join(SCENES, name), scenes / name)
    hide = can_hide_folders()
    if not hide:
        warnings.warn("the hosts see the sweep's folder (no mount namespace as this user): --return is not "
                      "told apart from the shared folder")
    hosts = sshd(hidden=shared if hide else None)
    if hide:
        r = hosts.ssh("host-a", f"ls -A {shared}")
        assert r.returncode == 0 and r.stdout == "", f"the hosts see {shared}: {r.stdout}{r.stderr}{hosts.log()}"
    spec = write_spec(shared / "spec.yaml", scenes)
    out = shared / "out"
    kill_half_way_then_resume(rtm, spec, out, ["--sshloginfile", str(hosts.sshloginfile), "--no-shared-dir"],
                              tmp_path)
    check_every_row_once(out, hosts.logins)
    for row in read_csv(out / "results.csv")[1]:
        assert {f"{row['run_id']}{ext}" for ext in (".row", ".json", ".err", ".png")} <= set(os.listdir(out / "runs"))
