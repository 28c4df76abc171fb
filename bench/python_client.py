#!/usr/bin/env python3
"""python_client.py: the `macsim` Python package beside the C++ client library, against the same
servers, measured in alternating blocks so both see the same machine noise:

  supervisor_rtt   a get_object round trip;
  step1_rtt        a lock-step Step(1) round trip;
  image_latency    a 640x480 bgr8 image from its send stamp to a numpy array (Python) or a
                   cv::Mat (C++), 30 Hz from bench_client --image-source.

One DDS domain holds macsim --lockstep on bench/worlds/empty_floor.xml (no robot) and the image
source (as robot kurt's left camera); each side has one participant on it.

Prints `name value unit` lines: p50 and p99 of each side and the ratios Python / C++.

    PYTHONPATH=build/python python3 bench/python_client.py --domain 60
"""

import argparse
import os
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools" / "python"))
import child_process  # noqa: E402  (the helpers of tests, tools and benchmarks)


def percentile(values, q):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def main():
    parser = argparse.ArgumentParser(prog="python_client.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--domain", type=int, required=True, help="DDS domain id, 0..232")
    parser.add_argument("--count", type=int, default=300, help="samples per part and block")
    parser.add_argument("--blocks", type=int, default=4, help="blocks per side (default 4)")
    parser.add_argument("--bin", default=str(ROOT / "build" / "bin"), help="the executables")
    args = parser.parse_args()
    if not 0 <= args.domain <= 232 or args.count < 1 or args.blocks < 1:
        parser.error("--domain is 0..232, --count and --blocks at least 1")
    os.environ.setdefault("FASTRTPS_DEFAULT_PROFILES_FILE",
                          str(ROOT / "deploy" / "dds" / "localhost.xml"))
    try:
        import macsim
    except ImportError as error:
        sys.exit(f"python_client: cannot import macsim ({error}): set PYTHONPATH=build/python")

    binary = Path(args.bin)
    d = args.domain
    servers = [
        subprocess.Popen([binary / "macsim", "--world", ROOT / "bench" / "worlds" /
                          "empty_floor.xml", "--lockstep", "--cameras", "off", "--domain",
                          str(d)], stdout=subprocess.DEVNULL),
        subprocess.Popen([binary / "bench_client", "--image-source", "--domain", str(d)]),
    ]
    try:
        participant = macsim.Participant(domain=d, name="bench_python")
        supervisor = macsim.Supervisor(participant, 20)
        simulation = macsim.Simulation(participant, 20)
        box = supervisor.find_object("box")
        simulation.step(1)

        def python_samples(part, count):
            samples = []
            if part == "image":
                # A reader of this block only, so that one side at a time takes the images.
                camera = macsim.Robot(participant)
                camera.image("left", timeout=20)
                last = -1.0
                while len(samples) < count:
                    frame = camera.camera("left", after=last)
                    samples.append((time.monotonic() - frame.stamp) * 1e6)
                    last = frame.stamp
                return samples
            call = (lambda: supervisor.get_object(box)) if part == "supervisor" else \
                (lambda: simulation.step(1))
            for _ in range(count):
                start = time.perf_counter()
                call()
                samples.append((time.perf_counter() - start) * 1e6)
            return samples

        # The C++ side: one long-lived process with its participant, asked for blocks.
        cpp = subprocess.Popen([binary / "bench_client", "--object", str(box), "--domain",
                                str(d)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               text=True)
        servers.append(cpp)
        if cpp.stdout.readline().strip() != "ready":
            sys.exit("python_client: bench_client found no macsim")

        def cpp_samples(part, count):
            cpp.stdin.write(f"{part} {count}\n")
            cpp.stdin.flush()
            samples = []
            for line in cpp.stdout:
                if line.strip() == "end":
                    return samples
                samples.append(float(line.split()[1]))
            sys.exit(f"python_client: bench_client stopped during {part}")

        results = {}
        sides = [("python", python_samples), ("cpp", cpp_samples)]
        for block in range(args.blocks):
            for part in ("supervisor", "step", "image"):
                count = args.count if part != "image" else max(10, args.count // 5)
                # Who goes first alternates, so neither always follows the other's block.
                for side, measure in sides if block % 2 == 0 else sides[::-1]:
                    # The first tenth of a block warms up (a new process's first calls).
                    samples = measure(part, count + count // 10)
                    results.setdefault((side, part), []).extend(samples[count // 10:])
        names = {"supervisor": "supervisor_rtt", "step": "step1_rtt", "image": "image_latency"}
        for part, name in names.items():
            for side in ("cpp", "python"):
                values = results[(side, part)]
                print(f"{side}.{name}.p50 {statistics.median(values):.1f} us")
                print(f"{side}.{name}.p99 {percentile(values, 0.99):.1f} us")
            python, cpp = results[("python", part)], results[("cpp", part)]
            print(f"{name}.python_over_cpp.p50 {statistics.median(python) / statistics.median(cpp):.3f} ratio")
        return 0
    finally:
        for server in servers:
            child_process.stop(server, signal.SIGINT, timeout=10)


if __name__ == "__main__":
    sys.exit(main())
