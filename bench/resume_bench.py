#!/usr/bin/env python3
"""Kills macsim (SIGKILL) at random instants of the final demonstrator and resumes it.

One outage at a time: a kill comes at its instant, or, if that is later, once the simulator
started after the last kill has served the controller and the killed one's DDS lease has run
out (kills in quicker succession are a known limit: see dds_bridge/README.md).

Each run plays kurt_demo on one seeded layout against `macsim --resume SESSION`; while it plays,
macsim is killed at random instants and started again on the same arguments, so that it resumes
from its session. A kill counts as survived when the resumed macsim came back (every recorded
hash met on the way: it refuses to resume otherwise) and the demonstrator still got through the
door. Lock-step runs must also be bit-identical to a run never killed: every state hash the two
sessions share is equal, and the demonstrator's robot time too. Real-time sessions, grown by
every resume, must replay whole (macsim --replay). Prints `name value unit` lines; exit 0 when
every kill was survived.

    bench/resume_bench.py [--build build] [--kills 20] [--modes lockstep,realtime]
"""
import argparse
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LEASE = 6.0  # s: the shipped profiles' participant lease (5 s), and a margin


def hashes(session):
    """step -> hash of a session's 'h' records."""
    out = {}
    with open(session) as f:
        for line in f:
            if line.startswith("h "):
                _, step, value = line.split()
                out[int(step)] = value
    return out


class Run:
    """One demonstrator run: macsim (killed and resumed as asked) and kurt_demo."""

    def __init__(self, args, mode, folder, name, domain):
        self.args, self.mode, self.folder = args, mode, folder
        self.session = os.path.join(folder, name + ".session")
        self.macsim_cmd = [os.path.join(args.build, "bin", "macsim"), "--world",
                           os.path.join(ROOT, "worlds", "DemoWorld_v1.xml"), "--seed",
                           str(args.seed), "--domain", str(domain), "--resume", self.session]
        if mode == "lockstep":
            self.macsim_cmd.append("--lockstep")
        self.demo_cmd = [os.path.join(args.build, "bin", "kurt_demo"), "--domain", str(domain)]
        if mode == "lockstep":
            self.demo_cmd.append("--lockstep")
        self.logs = []
        self.resume_seconds = []

    def start_macsim(self):
        log = open(self.session + f".macsim{len(self.logs)}.log", "w+")
        self.logs.append(log)
        proc = subprocess.Popen(self.macsim_cmd, stdout=log, stderr=subprocess.STDOUT)
        ready = "stepping on request" if self.mode == "lockstep" else "stepping at real-time"
        deadline = time.time() + 120
        while time.time() < deadline:
            log.seek(0)
            text = log.read()
            if ready in text:
                m = re.search(r"resumed \S+ at step \d+ \(sim time [0-9.]+ s\) in ([0-9.]+) s", text)
                if m:
                    self.resume_seconds.append(float(m.group(1)))
                return proc
            if proc.poll() is not None:
                raise RuntimeError(f"macsim ended ({proc.returncode}):\n{text[-2000:]}")
            time.sleep(0.05)
        raise RuntimeError("macsim did not start")

    def play(self, kill_at):
        """Plays the demonstrator, killing macsim at each wall time in `kill_at` (s after the
        start); returns (demo exit code, demo output, kills done)."""
        macsim = self.start_macsim()
        demo_log = open(self.session + ".demo.log", "w+")
        demo = subprocess.Popen(self.demo_cmd, stdout=demo_log, stderr=subprocess.STDOUT)
        start, kills = time.time(), 0
        try:
            for at in sorted(kill_at):
                # At the instant, once the simulator started last has served the controller
                # (the session grew after its resume) and the killed one's lease (5 s) ran
                # out: one outage at a time.
                served = os.path.getsize(self.session) if kills else 0
                restarted = time.time()
                while (time.time() - start < at or
                       (kills and (os.path.getsize(self.session) <= served + 2000 or
                                   time.time() - restarted < LEASE))) \
                        and demo.poll() is None:
                    time.sleep(0.01)
                if demo.poll() is not None:
                    break
                macsim.send_signal(signal.SIGKILL)
                macsim.wait()
                kills += 1
                macsim = self.start_macsim()
            demo.wait(timeout=900)
        finally:
            if demo.poll() is None:
                demo.kill()
                demo.wait()
            macsim.send_signal(signal.SIGTERM)
            macsim.wait(timeout=60)
        demo_log.seek(0)
        return demo.returncode, demo_log.read(), kills


def robot_time(output):
    m = re.search(r"robot time ([0-9.]+) s", output)
    return m.group(1) if m else None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.environ.get("MACSIM_BUILD_DIR", os.path.join(ROOT, "build")))
    parser.add_argument("--kills", type=int, default=20, help="kills in each mode (default 20)")
    parser.add_argument("--per-run", type=int, default=5, help="kills in one run (default 5)")
    parser.add_argument("--modes", default="lockstep,realtime")
    parser.add_argument("--seed", type=int, default=5, help="the layout (default 5)")
    parser.add_argument("--domain", type=int, default=None, help="DDS domain (default: 90+pid%%9, below the tests' 100-232)")
    parser.add_argument("--random-seed", type=int, default=None)
    args = parser.parse_args()
    if args.kills < 1 or args.per_run < 1:
        parser.error("--kills and --per-run must be at least 1")
    domain = args.domain if args.domain is not None else 90 + os.getpid() % 9
    rng = random.Random(args.random_seed if args.random_seed is not None else time.time_ns())
    os.environ.setdefault("FASTRTPS_DEFAULT_PROFILES_FILE",
                          os.path.join(ROOT, "deploy", "dds", "localhost.xml"))
    failures = []
    folder = tempfile.mkdtemp(prefix="macsim_resume_bench_")
    try:
        for mode in args.modes.split(","):
            if mode not in ("lockstep", "realtime"):
                parser.error(f"unknown mode '{mode}'")
            reference = Run(args, mode, folder, f"{mode}_reference", domain)
            t0 = time.time()
            code, output, _ = reference.play([])
            length = time.time() - t0
            if code != 0:
                failures.append(f"{mode}: the run never killed failed ({code}):\n{output[-1500:]}")
                continue
            reference_time = robot_time(output)
            print(f"resume.{mode}.demo_wall {length:.1f} s", flush=True)
            survived = kills = runs = 0
            resume_seconds = []
            while kills < args.kills:
                n = min(args.per_run, args.kills - kills)
                # Random instants within the demonstrator's wall time (resumes lengthen it).
                instants = sorted(rng.uniform(0.5, 0.95 * length) for _ in range(n))
                run = Run(args, mode, folder, f"{mode}_{runs}", domain)
                code, output, done = run.play(instants)
                runs += 1
                kills += done
                if runs >= 4 * args.kills:
                    failures.append(f"{mode}: the demonstrator ends before its kills come")
                    break
                resume_seconds += run.resume_seconds
                ok = code == 0 and "SUCCESS" in output and len(run.resume_seconds) == done
                why = "" if ok else f"kurt_demo exit {code}, {len(run.resume_seconds)} of {done} resumed"
                if ok and mode == "lockstep":
                    same = robot_time(output) == reference_time
                    a, b = hashes(run.session), hashes(reference.session)
                    shared = set(a) & set(b)
                    differ = [s for s in shared if a[s] != b[s]]
                    ok = same and not differ and len(shared) > 0.9 * len(b)
                    why = f"robot time same: {same}, {len(differ)} of {len(shared)} hashes differ"
                if ok and mode == "realtime":
                    replay = subprocess.run([run.macsim_cmd[0], "--replay", run.session],
                                            capture_output=True, text=True, timeout=600)
                    ok = replay.returncode == 0
                    why = f"replay: {replay.stdout.strip()[-300:]}"
                if ok:
                    survived += done
                else:
                    failures.append(f"{mode} run {runs} (kills at {instants}): {why}\n"
                                    f"{output[-1500:]}")
                print(f"# {mode} run {runs}: {done} kills, {'ok' if ok else 'FAILED: ' + why}",
                      flush=True)
            print(f"resume.{mode}.kills {kills} kills")
            print(f"resume.{mode}.survived {survived} kills")
            if resume_seconds:
                resume_seconds.sort()
                print(f"resume.{mode}.resume_median {resume_seconds[len(resume_seconds) // 2]:.2f} s")
                print(f"resume.{mode}.resume_max {resume_seconds[-1]:.2f} s")
            sys.stdout.flush()
    finally:
        if not failures:
            shutil.rmtree(folder, ignore_errors=True)
    for failure in failures:
        print("FAILED: " + failure, file=sys.stderr)
    if failures:
        print(f"(logs kept in {folder})", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
