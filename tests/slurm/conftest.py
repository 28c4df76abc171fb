"""A one-node Slurm cluster of the test's own, from Debian's slurm-wlm and munge, started as
root: its own munge key and munged (socket, pid, log and seed files in a temporary folder), a
slurm.conf of its own (private ports, no cgroups, spool and state in the same folder; SLURM_CONF
set for every command), slurmctld and slurmd, stopped by their pid files. Nothing under
/etc/munge or /etc/slurm is read for the cluster or written.

The test process is the cluster's child subreaper: slurmd double-forks slurmstepd, and a
process orphaned anywhere in the cluster comes back to the test (and is reaped by it) instead
of going to PID 1. So "the cluster left nothing behind" means: no descendant of the test, and no
process carrying the cluster's marker (an environment variable every daemon and job inherits).
"""

import ctypes
import fcntl
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import uuid
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("MACSIM_SOURCE_DIR", Path(__file__).resolve().parents[2]))
BIN_DIR = Path(os.environ.get("MACSIM_BIN_DIR", SOURCE_DIR / "build" / "bin"))
SLURM_DIR = SOURCE_DIR / "deploy" / "slurm"
PROFILE = SOURCE_DIR / "deploy" / "dds" / "localhost.xml"
MARKER = "MACSIM_SLURM_TEST_MARKER"
# DDS traffic of tests stays on this machine.
os.environ.setdefault("FASTRTPS_DEFAULT_PROFILES_FILE", str(PROFILE))
PR_SET_CHILD_SUBREAPER = 36
# The Python helpers of tests, tools and benchmarks.
sys.path.insert(0, str(SOURCE_DIR / "tools" / "python"))
import child_process  # noqa: E402


def lock_domains(count):
    """`count` consecutive free DDS domains in 100..232, held (flock, the lock files of every
    test of the project) until the returned descriptors are closed."""
    first_possible, span = 100, 133
    offset = os.getpid() % span
    for i in range(span):
        first = first_possible + (offset + i) % span
        if first + count > first_possible + span:
            continue
        held = []
        for domain in range(first, first + count):
            fd = os.open(f"/tmp/macsim-test-domain-{domain}.lock", os.O_CREAT | os.O_RDWR, 0o666)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                held.append(fd)
            except OSError:
                os.close(fd)
                break
        if len(held) == count:
            return first, held
        for fd in held:
            os.close(fd)
    raise RuntimeError(f"no {count} free consecutive DDS test domains in 100..232")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _status(pid):
    """The /proc status fields of a process, or None when there is none."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return None
    return dict(line.split(":\t", 1) for line in text.splitlines() if ":\t" in line)


def descendants(root=None):
    """{pid: command line} of every process below `root` (default: this process)."""
    root = root or os.getpid()
    parent = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            status = _status(entry)
            if status:
                parent[int(entry)] = int(status["PPid"])
    found = {}
    for pid in parent:
        p = pid
        while p in parent and p > 1:
            p = parent[p]
            if p == root:
                found[pid] = _cmdline(pid)
                break
    return found


def _cmdline(pid):
    try:
        raw = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return ""
    return raw.replace(b"\0", b" ").decode(errors="replace").strip() or f"[{pid} zombie]"


def marked(marker):
    """{pid: command line} of every process whose environment holds the marker."""
    needle = f"{MARKER}={marker}".encode()
    found = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            environ = Path(f"/proc/{entry}/environ").read_bytes()
        except OSError:
            continue
        if needle in environ.split(b"\0"):
            found[int(entry)] = _cmdline(entry)
    return found


class Cluster:
    def __init__(self, root):
        self.root = Path(root)
        self.marker = uuid.uuid4().hex
        self.host = socket.gethostname().split(".")[0]
        self.conf = self.root / "etc" / "slurm.conf"
        self.socket = self.root / "run" / "munge.socket"
        self.daemons = {}  # name -> (Popen, pid file)
        self.env = dict(os.environ, SLURM_CONF=str(self.conf),
                        FASTRTPS_DEFAULT_PROFILES_FILE=str(PROFILE), **{MARKER: self.marker})
        for key in [k for k in self.env if k.startswith(("SLURM_", "SBATCH_", "SQUEUE_"))]:
            if key != "SLURM_CONF":
                del self.env[key]
        self.stopped = False

    def path(self, *parts):
        return self.root.joinpath(*parts)

    def log_tails(self):
        text = []
        for name in ["munged.log", "slurmctld.log", "slurmd.log"]:
            log = self.path("log", name)
            if log.exists():
                text.append(f"--- {name}\n" + "\n".join(log.read_text(errors="replace").splitlines()[-25:]))
        return "\n".join(text)

    def _daemon(self, name, argv, pid_file):
        log = open(self.path("log", f"{name}.out"), "wb")
        process = subprocess.Popen(argv, env=self.env, stdout=log, stderr=subprocess.STDOUT,
                                   stdin=subprocess.DEVNULL, start_new_session=True)
        log.close()
        self.daemons[name] = (process, pid_file)
        deadline = time.monotonic() + 15
        while time.monotonic() < deadline:
            if pid_file.exists() and pid_file.read_text().strip() == str(process.pid):
                return
            if process.poll() is not None:
                break
            time.sleep(0.05)
        raise RuntimeError(f"{name} did not start (exit {process.poll()}):\n{self.log_tails()}\n"
                           + self.path("log", f"{name}.out").read_text(errors="replace"))

    def start(self):
        for sub in ["etc", "run", "log", "state", "spool", "munge"]:
            self.path(sub).mkdir(parents=True, exist_ok=True)
        # munged wants its socket's folder open to all (execute), its key private to its user.
        os.chmod(self.root, 0o755)
        os.chmod(self.path("run"), 0o755)
        os.chmod(self.path("munge"), 0o700)
        key = self.path("munge", "munge.key")
        subprocess.run(["mungekey", "--create", "--keyfile", str(key)], check=True, env=self.env)
        os.chmod(key, 0o400)
        self._daemon("munged", ["munged", "--foreground", "--socket", str(self.socket),
                                "--pid-file", str(self.path("run", "munged.pid")),
                                "--log-file", str(self.path("log", "munged.log")),
                                "--seed-file", str(self.path("munge", "munged.seed")),
                                "--key-file", str(key)],
                     self.path("run", "munged.pid"))
        ctld_port, d_port = free_port(), free_port()
        while d_port == ctld_port:
            d_port = free_port()
        self.path("etc", "plugstack.conf").write_text("")
        root = self.root
        self.conf.write_text(f"""# A one-node cluster of the slurm test (tests/slurm/conftest.py).
ClusterName=macsimtest
SlurmctldHost={self.host}(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={d_port}
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.socket}
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
SlurmUser=root
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
PlugStackConfig={root}/etc/plugstack.conf
StateSaveLocation={root}/state
SlurmdSpoolDir={root}/spool
SlurmctldPidFile={root}/run/slurmctld.pid
SlurmdPidFile={root}/run/slurmd.pid
SlurmctldLogFile={root}/log/slurmctld.log
SlurmdLogFile={root}/log/slurmd.log
ReturnToService=2
KillWait=5
MinJobAge=600
NodeName={self.host} NodeAddr=127.0.0.1 CPUs={os.cpu_count()} State=UNKNOWN
PartitionName=test Nodes={self.host} Default=YES MaxTime=INFINITE State=UP
""")
        self._daemon("slurmctld", ["slurmctld", "-D", "-f", str(self.conf)],
                     self.path("run", "slurmctld.pid"))
        self._daemon("slurmd", ["slurmd", "-D", "-f", str(self.conf)], self.path("run", "slurmd.pid"))
        deadline = time.monotonic() + 30
        state = ""
        while time.monotonic() < deadline:
            state = self.run(["sinfo", "-h", "-N", "-o", "%t"], check=False).stdout.strip()
            if state == "idle":
                return
            time.sleep(0.2)
        raise RuntimeError(f"the node is '{state}', not idle, after 30 s:\n{self.log_tails()}")

    def run(self, argv, check=True, timeout=60, **kwargs):
        result = subprocess.run([str(a) for a in argv], env=self.env, capture_output=True,
                                text=True, timeout=timeout, stdin=subprocess.DEVNULL, **kwargs)
        if check:
            assert result.returncode == 0, f"{argv}: exit {result.returncode}\n{result.stdout}\n{result.stderr}"
        return result

    def job(self, job_id):
        """scontrol's fields of a job (an array task as ARRAY_TASK), or {} once forgotten."""
        result = self.run(["scontrol", "-o", "show", "job", job_id], check=False)
        if result.returncode != 0 or not result.stdout.strip():
            return {}
        fields = {}
        for item in result.stdout.splitlines()[0].split():
            if "=" in item:
                key, value = item.split("=", 1)
                fields.setdefault(key, value)
        return fields

    def array_tasks(self, job_id):
        """{task id: scontrol's fields} of a job array's tasks."""
        result = self.run(["scontrol", "-o", "show", "job", job_id], check=False)
        tasks = {}
        for line in result.stdout.splitlines():
            fields = dict(item.split("=", 1) for item in line.split() if "=" in item)
            if fields.get("ArrayTaskId", "").isdigit():
                tasks[int(fields["ArrayTaskId"])] = fields
        return tasks

    def wait_job(self, job_id, timeout=120):
        """Waits until the job has ended; its scontrol fields."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.reap()
            fields = self.job(job_id)
            if fields.get("JobState") not in (None, "PENDING", "RUNNING", "CONFIGURING",
                                              "COMPLETING"):
                return fields
            if fields.get("Reason") == "DependencyNeverSatisfied":
                return fields
            time.sleep(0.2)
        raise AssertionError(f"job {job_id} still {self.job(job_id).get('JobState')} after "
                             f"{timeout} s\n{self.log_tails()}")

    def reap(self):
        """Reaps the cluster's orphans that ended (they came to this process, the subreaper)."""
        ours = {process.pid for process, _ in self.daemons.values()}
        for pid in descendants():
            status = _status(pid)
            if pid not in ours and status and status.get("PPid") == str(os.getpid()) \
                    and status.get("State", "").startswith("Z"):
                try:
                    os.waitpid(pid, os.WNOHANG)
                except ChildProcessError:
                    pass

    def processes(self):
        """{pid: command line} of the cluster's processes: the test's descendants (but for its
        own short commands, which have ended) and whatever carries the marker."""
        return {**descendants(), **marked(self.marker)}

    def stop(self):
        """Cancels every job, waits for their processes to end, stops slurmd, slurmctld and
        munged by their pid files. Returns what was left (and then killed) as {pid: command}."""
        if self.stopped:
            return {}
        self.stopped = True
        leftovers = {}
        if "slurmctld" in self.daemons and self.daemons["slurmctld"][0].poll() is None:
            self.run(["scancel", "--user", "root"], check=False)
            deadline = time.monotonic() + 30
            while time.monotonic() < deadline:
                self.reap()
                queue = self.run(["squeue", "-h", "-o", "%i"], check=False).stdout.strip()
                steps = [c for c in self.processes().values() if "slurmstepd" in c or "slurm_script" in c]
                if not queue and not steps:
                    break
                time.sleep(0.2)
        for name in ["slurmd", "slurmctld", "munged"]:
            if name not in self.daemons:
                continue
            process, pid_file = self.daemons[name]
            if process.poll() is None:
                pid = int(pid_file.read_text()) if pid_file.exists() else process.pid
                assert pid == process.pid, f"{pid_file} names {pid}, not {name} ({process.pid})"
                if not child_process.stop(process, signal.SIGTERM, timeout=20):
                    leftovers[process.pid] = f"{name} (ignored SIGTERM for 20 s)"
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and self.processes():
            self.reap()
            time.sleep(0.1)
        for pid, command in self.processes().items():
            leftovers[pid] = command
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        time.sleep(0.2)
        self.reap()
        return leftovers


@pytest.fixture(scope="module")
def cluster():
    if os.geteuid() != 0:
        pytest.skip("a Slurm cluster of the test's own needs root (slurmd runs jobs as their user)")
    for program in ["munged", "mungekey", "slurmctld", "slurmd", "sbatch", "sinfo", "scancel"]:
        assert shutil.which(program), f"{program} missing: deploy/install_deps.sh installs slurm-wlm and munge"
    libc = ctypes.CDLL(None, use_errno=True)
    assert libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) == 0, "prctl(PR_SET_CHILD_SUBREAPER)"
    root = tempfile.mkdtemp(prefix="macsim-slurm-")
    c = Cluster(root)
    try:
        c.start()
        yield c
    finally:
        left = c.stop()
        libc.prctl(PR_SET_CHILD_SUBREAPER, 0, 0, 0, 0)
        subprocess.run([str(BIN_DIR / "macsim_shm_clean")], capture_output=True)
        shutil.rmtree(root, ignore_errors=True)
        assert not left, f"left behind by the cluster (killed): {left}"


@pytest.fixture(scope="module")
def domains():
    """Five consecutive DDS domains: four for the array's tasks, one for the one-process run."""
    first, fds = lock_domains(5)
    yield first
    for fd in fds:
        os.close(fd)


# When every test was skipped (not root), pytest's exit is 77, which ctest reports as skipped
# (SKIP_RETURN_CODE) rather than passed.
_outcomes = set()


def pytest_runtest_logreport(report):
    if report.when == "call" or report.outcome != "passed":
        _outcomes.add(report.outcome)


def pytest_sessionfinish(session, exitstatus):
    if exitstatus == 0 and _outcomes == {"skipped"}:
        session.exitstatus = 77
