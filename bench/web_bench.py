#!/usr/bin/env python3
"""web_bench.py: what macsim_web costs the simulator, and how late the page shows a change.

1. Step rate: macsim as fast as possible on the demo world (cameras off), measured over
   --seconds by its own status, alone, with macsim_web serving no browser, with one browser
   and with five (headless Chromium, each its own session), the set-ups taken in turn for
   --rounds rounds; medians and the ratios to macsim alone.
2. Latency: macsim in real time; a box moved through the supervisor 30 times; the time from
   a Python subscriber of the world state seeing the new pose to the page applying it (both
   on this machine's wall clock).

Prints `name value unit` lines.

    PYTHONPATH=build/python python3 bench/web_bench.py --domain 80
"""

import argparse
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools" / "python"))
import child_process  # noqa: E402  (the helpers of tests, tools and benchmarks)


def percentile(values, q):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


class Child:
    """A process with its output in a file (never a pipe that could fill up)."""

    def __init__(self, argv):
        self.log = tempfile.TemporaryFile()
        self.process = subprocess.Popen([str(a) for a in argv], stdout=self.log,
                                        stderr=subprocess.STDOUT, start_new_session=True)

    def wait_for(self, text, timeout=30):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.log.seek(0)
            for line in self.log.read().decode(errors="replace").splitlines():
                if text in line:
                    return line
            if self.process.poll() is not None:
                break
            time.sleep(0.05)
        raise RuntimeError(f"did not see '{text}'")

    def stop(self):
        child_process.stop(self.process, signal.SIGINT, timeout=10, group=True)


def main():
    parser = argparse.ArgumentParser(prog="web_bench.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--domain", type=int, required=True, help="DDS domain id, 0..232")
    parser.add_argument("--seconds", type=float, default=5.0, help="per measurement (default 5)")
    parser.add_argument("--rounds", type=int, default=3, help="rounds of the set-ups (default 3)")
    parser.add_argument("--bin", default=str(ROOT / "build" / "bin"), help="the executables")
    args = parser.parse_args()
    if not 0 <= args.domain <= 232 or args.seconds <= 0 or args.rounds < 1:
        parser.error("--domain is 0..232, --seconds > 0, --rounds >= 1")
    os.environ.setdefault("FASTRTPS_DEFAULT_PROFILES_FILE",
                          str(ROOT / "deploy" / "dds" / "localhost.xml"))
    import headless_chromium
    import macsim

    binary = Path(args.bin)
    d = args.domain
    world = ROOT / "worlds" / "DemoWorld_v1.xml"
    participant = macsim.Participant(domain=d, name="web_bench")
    simulation = macsim.Simulation(participant, timeout=20)
    children, pages = [], []  # pages: the browsers open

    def close(page):
        pages.remove(page)
        page.quit()

    def web():
        child = Child([binary / "macsim_web", "--domain", d, "--port", "0"])
        children.append(child)
        url = re.search(r"serving (http://\S+)", child.wait_for("serving http://")).group(1)
        return child, url

    def browsers(url, count):
        opened = []
        for _ in range(count):
            b = headless_chromium.start()
            pages.append(b)
            b.get(url)
            opened.append(b)
        for b in opened:
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline:
                v = b.execute_script("return window.macsimView || null;")
                if v and v["drawn"] > 0 and v["updates"] > 5:
                    break
                time.sleep(0.2)
        return opened

    try:
        # 1. Step rate.
        sim = Child([binary / "macsim", "--world", world, "--as-fast-as-possible", "--cameras",
                     "off", "--domain", d])
        children.append(sim)
        sim.wait_for("stepping")
        rates = {}
        setups = [("alone", None), ("web_no_browser", 0), ("one_browser", 1),
                  ("five_browsers", 5)]
        for _ in range(args.rounds):
            for name, count in setups:
                server, opened = None, []
                if count is not None:
                    server, url = web()
                    opened = browsers(url, count)
                    time.sleep(1.0)
                first = simulation.status()
                start = time.monotonic()
                time.sleep(args.seconds)
                last = simulation.status()
                rates.setdefault(name, []).append((last.steps - first.steps) /
                                                  (time.monotonic() - start))
                for b in opened:
                    close(b)
                if server:
                    server.stop()
        sim.stop()
        alone = statistics.median(rates["alone"])
        for name, _ in setups:
            rate = statistics.median(rates[name])
            print(f"macsim_steps_per_s.{name} {rate:.0f} steps/s")
            if name != "alone":
                print(f"macsim_steps_per_s.{name}.ratio_to_alone {rate / alone:.3f} ratio")

        # 2. Latency of a pose change, from the world state topic to the page.
        sim = Child([binary / "macsim", "--world", world, "--cameras", "off", "--domain", d])
        children.append(sim)
        sim.wait_for("stepping")
        server, url = web()
        [page] = browsers(url, 1)
        supervisor = macsim.Supervisor(participant)
        state = macsim.WorldState(participant)
        box = supervisor.find_object(next(name for name in supervisor.list_objects().values()
                                          if "can" in name))
        page.execute_script(f"window.macsimView.watched.add({box});")
        origin = supervisor.get_object(box).position
        seen = []
        for k in range(30):
            target = (origin[0] + 0.2 * (k % 2 + 1), origin[1], origin[2] + 0.3)
            supervisor.set_position(box, target, allow_penetration=True)
            deadline = time.monotonic() + 5
            while time.monotonic() < deadline:
                now = state.objects().get(box)
                if now and abs(now.position[0] - target[0]) < 1e-3:
                    seen.append((time.time() * 1000.0, target[0]))
                    break
                time.sleep(0.001)
            time.sleep(0.3)
        changes = page.execute_script(f"return window.macsimView.changes['{box}'] || [];")
        latencies = []
        for dds_ms, x in seen:
            later = [t for t, cx, _, _ in changes if abs(cx - x) < 2e-3 and t >= dds_ms - 50]
            if later:
                latencies.append(min(later) - dds_ms)
        close(page)
        print(f"web_latency.changes {len(latencies)} of {len(seen)} count")
        print(f"web_latency.p50 {statistics.median(latencies):.1f} ms")
        print(f"web_latency.p95 {percentile(latencies, 0.95):.1f} ms")
        return 0
    finally:
        for page in list(pages):
            close(page)
        for child in reversed(children):
            child.stop()


if __name__ == "__main__":
    sys.exit(main())
