#!/usr/bin/env python3
"""hello_kurt.py: helloKurt in Python. Drives a KURT3D forward by a distance measured by its
odometry, then stops, over DDS, against whichever participant serves the robot's topics (the
simulator or the real robot's adapter).

Exit 0: arrived; 1: timeout; 2: usage or no robot found; 3: the robot went silent and did not
come back.

    PYTHONPATH=build/python python3 examples/python/hello_kurt.py --domain 7
"""

import argparse
import math
import sys
import time

try:
    import macsim
except ImportError as error:
    sys.exit(f"hello_kurt: cannot import macsim ({error}): build the project and set "
             "PYTHONPATH=build/python")


def positive(text):
    value = float(text)
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"must be a positive number, not {text}")
    return value


def planar_distance(a, b):
    return math.hypot(a.position[0] - b.position[0], a.position[1] - b.position[1])


def main():
    parser = argparse.ArgumentParser(
        prog="hello_kurt.py",
        description="Drives a KURT3D forward by a distance measured by its odometry, then stops. "
        "Exit 0: arrived; 1: timeout; 2: usage or no robot found; 3: the robot went silent and "
        "did not come back.")
    parser.add_argument("--domain", type=int, required=True, help="DDS domain id, 0..232")
    parser.add_argument("--profile", help="Fast DDS XML profile file "
                        "(default: $FASTRTPS_DEFAULT_PROFILES_FILE)")
    parser.add_argument("--robot", default="kurt", help="robot namespace (default kurt)")
    parser.add_argument("--distance", type=positive, default=1.0, help="metres (default 1.0)")
    parser.add_argument("--speed", type=positive, default=0.3, help="cruise m/s (default 0.3)")
    parser.add_argument("--timeout", type=positive, default=60.0,
                        help="give up after this many seconds (default 60)")
    parser.add_argument("--discovery-timeout", type=positive, default=15.0,
                        help="wait this long for the robot (default 15)")
    parser.add_argument("--reconnect-timeout", type=float, default=30.0,
                        help="when the robot goes silent, wait this long for it (default 30)")
    args = parser.parse_args()
    if not 0 <= args.domain <= 232 or args.reconnect_timeout < 0:
        parser.error("--domain is 0..232 and --reconnect-timeout >= 0")

    participant = macsim.Participant(domain=args.domain, profile=args.profile, name="hello_kurt")
    kurt = macsim.Robot(participant, args.robot)
    print(f"hello_kurt: looking for robot '{args.robot}' on DDS domain {args.domain} ...",
          flush=True)
    try:
        start = kurt.odometry(timeout=args.discovery_timeout)
    except TimeoutError as error:
        print(f"hello_kurt: {error}", file=sys.stderr)
        return 2
    print(f"hello_kurt: found '{args.robot}' at odometry ({start.position[0]:.3f}, "
          f"{start.position[1]:.3f}); driving {args.distance:.2f} m at {args.speed:.2f} m/s",
          flush=True)

    deadline = time.monotonic() + args.timeout
    travelled = before_outages = 0.0
    next_report = 0.1
    tolerance = 0.005
    while True:
        try:
            odom = kurt.odometry(timeout=2.0)
        except TimeoutError:
            print(f"hello_kurt: robot '{args.robot}' went silent; waiting up to "
                  f"{args.reconnect_timeout:.0f} s for it", file=sys.stderr)
            try:
                odom = kurt.odometry(timeout=args.reconnect_timeout)
            except TimeoutError:
                kurt.stop()
                print(f"hello_kurt: robot '{args.robot}' went silent and did not come back",
                      file=sys.stderr)
                return 3
            # Its odometry may have started again (a restarted simulator): count from here on.
            before_outages, start = travelled, odom
            print(f"hello_kurt: robot '{args.robot}' is back; "
                  f"{args.distance - travelled:.2f} m to go", flush=True)
        travelled = before_outages + planar_distance(odom, start)
        remaining = args.distance - travelled
        if remaining <= tolerance:
            break
        if time.monotonic() > deadline:
            kurt.stop()
            print(f"hello_kurt: did not arrive within {args.timeout:.0f} s (travelled "
                  f"{travelled:.3f} of {args.distance:.3f} m)", file=sys.stderr)
            return 1
        # Slow down near the goal; never below what the robot's 1 cm/s steps can express.
        kurt.cmd_vel(min(max(1.5 * remaining, 0.05), args.speed), 0.0)
        if travelled >= next_report:
            print(f"hello_kurt: {travelled:.2f} m  (odometry x {odom.position[0]:.3f}, "
                  f"y {odom.position[1]:.3f}, v {odom.linear_velocity[0]:.2f} m/s)", flush=True)
            next_report += 0.1
        time.sleep(0.05)

    # Stop and wait until the odometry says the robot stands.
    for _ in range(40):
        kurt.stop()
        try:
            odom = kurt.odometry(timeout=0.5)
        except TimeoutError:
            continue
        if abs(odom.linear_velocity[0]) < 1e-6:
            travelled = before_outages + planar_distance(odom, start)
            break
        time.sleep(0.025)
    print(f"hello_kurt: arrived: travelled {travelled:.3f} m by odometry "
          f"(goal {args.distance:.3f} m)")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
