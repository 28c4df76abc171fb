"""Fixtures of the Python suite: a DDS domain of its own per test (the same lock files as the
C++ tests, so the suites never share one), processes that are always reaped, and macsim
started the way a user starts it."""

import contextlib
import fcntl
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("MACSIM_SOURCE_DIR", Path(__file__).resolve().parents[2]))
BIN_DIR = Path(os.environ.get("MACSIM_BIN_DIR", SOURCE_DIR / "build" / "bin"))
# The Python helpers of tests, tools and benchmarks (child_process, headless_chromium).
sys.path.insert(0, str(SOURCE_DIR / "tools" / "python"))
import child_process  # noqa: E402
# DDS traffic of tests stays on this machine.
os.environ.setdefault("FASTRTPS_DEFAULT_PROFILES_FILE",
                      str(SOURCE_DIR / "deploy" / "dds" / "localhost.xml"))


def source(relative):
    return str(SOURCE_DIR / relative)


def binary(name):
    return str(BIN_DIR / name)


def _lock_domain():
    """A free DDS domain in 100..232, held by an flock for as long as the descriptor is open."""
    first, count = 100, 133
    offset = os.getpid() % count
    for i in range(count):
        domain = first + (offset + i) % count
        fd = os.open(f"/tmp/macsim-test-domain-{domain}.lock", os.O_CREAT | os.O_RDWR, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return domain, fd
        except OSError:
            os.close(fd)
    raise RuntimeError("no free DDS test domain in 100..232")


@contextlib.contextmanager
def held_domain():
    """A free DDS test domain, held until the block ends."""
    number, fd = _lock_domain()
    try:
        yield number
    finally:
        os.close(fd)


@pytest.fixture
def domain():
    with held_domain() as number:
        yield number


class Process:
    """A child process with its output in a file; stop() ends and reaps it."""

    def __init__(self, argv, env=None):
        self.argv = argv
        self.log = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(argv, stdout=self.log, stderr=subprocess.STDOUT,
                                     stdin=subprocess.DEVNULL, env=env, start_new_session=True)

    def output(self):
        self.log.seek(0)
        return self.log.read().decode(errors="replace")

    def wait_for_output(self, text, timeout=30.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if text in self.output():
                return True
            if self.proc.poll() is not None:
                return text in self.output()
            time.sleep(0.05)
        return False

    def wait(self, timeout):
        return self.proc.wait(timeout=timeout)

    def stop(self):
        child_process.stop(self.proc, signal.SIGINT, timeout=10, group=True)
        self.log.close()


@contextlib.contextmanager
def spawning():
    """start(argv, env=None) -> Process; every process started is stopped and reaped, newest
    first, when the block ends."""
    started = []

    def start(argv, env=None):
        process = Process([str(a) for a in argv], env)
        started.append(process)
        return process

    try:
        yield start
    finally:
        for process in reversed(started):
            process.stop()


@pytest.fixture
def spawn():
    with spawning() as start:
        yield start


def start_macsim(spawn, domain, world, *options, ready="stepping"):
    process = spawn([binary("macsim"), "--world", source(world), "--domain", domain, *options])
    assert process.wait_for_output(ready, 60), process.output()
    return process
