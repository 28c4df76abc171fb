#!/usr/bin/env python3
"""liftability.py: a few liftability trials in lock-step through the supervisor.

Each trial puts the world back as loaded, spawns one object under the KURT3D's crane, lowers
the magnet onto it, switches the magnet on, raises the boom and holds: the object is liftable
when it came up 5 cm and stayed up. The simulator steps only when asked (macsim --lockstep),
so every run prints the same table, state hashes included.

    build/bin/macsim --world worlds/affordance_trials.xml --lockstep --cameras off --domain 7 &
    PYTHONPATH=build/python python3 examples/python/liftability.py --domain 7
"""

import argparse
import math
import sys
import time

try:
    import macsim
except ImportError as error:
    sys.exit(f"liftability: cannot import macsim ({error}): build the project and set "
             "PYTHONPATH=build/python")

# The KURT3D's crane, from its description: base height, boom pivot, boom length, and how far
# the magnet hangs below the boom's tip with the hoist in. The robot starts at the origin,
# facing +x.
KURT = macsim.kurt3d_description()
BASE_HEIGHT, PIVOT_X, PIVOT_Z = KURT["base_height"], KURT["pivot_x"], KURT["pivot_height"]
BOOM, MAGNET_BELOW_TIP = KURT["boom_length"], KURT["magnet_below_tip"]
STEP = 0.002  # s, the physics step of worlds/affordance_trials.xml

# name, shape, size (m), mass (kg), magnetizable, colour
TRIALS = [
    ("light_iron_box", macsim.SHAPE_BOX, (0.06, 0.06, 0.06), 0.1, True, (0.8, 0.1, 0.1, 1)),
    ("light_wood_box", macsim.SHAPE_BOX, (0.06, 0.06, 0.06), 0.1, False, (0.8, 0.6, 0.3, 1)),
    ("heavy_iron_box", macsim.SHAPE_BOX, (0.08, 0.08, 0.08), 20.0, True, (0.1, 0.1, 0.8, 1)),
    ("iron_can", macsim.SHAPE_CYLINDER, (0.03, 0, 0.07), 0.15, True, (0.7, 0.7, 0.7, 1)),
]


def advance(simulation, robot, seconds):
    """Steps the simulator `seconds` of sim time; the step request names the robot's commands
    sent before it, and the simulator waits for them before its first step."""
    return simulation.step(max(1, round(seconds / STEP)))


def trial(simulation, supervisor, robot, name, shape, size, mass, magnetizable, color):
    simulation.reset(macsim.RESET_EVERYTHING)
    height = size[2]
    top = height
    # The boom low enough that the magnet hangs 2 cm over the object's top, then the object
    # right under the magnet, straight ahead.
    lift = math.asin((top + MAGNET_BELOW_TIP + 0.02 - BASE_HEIGHT - PIVOT_Z) / BOOM)
    x = PIVOT_X + BOOM * math.cos(lift)
    object_id = supervisor.create_object(
        name, [macsim.Component(shape, size, color=color)], position=(x, 0.0, height / 2 + 0.001),
        mass=mass, magnetizable=magnetizable, user_data="liftability")
    z0 = supervisor.get_object(object_id).position[2]

    robot.crane(0.0, lift, 0.0)
    advance(simulation, robot, 2.0)
    # Down onto it with the magnet on, 1.5 cm further than the top: the magnet rests on it.
    tip_z = BASE_HEIGHT + PIVOT_Z + BOOM * math.sin(lift)
    robot.magnet(True)
    robot.crane(0.0, lift, tip_z - MAGNET_BELOW_TIP - top + 0.015)
    advance(simulation, robot, 1.0)
    # Up: the hoist in and the boom 0.3 rad higher; hold a second.
    robot.crane(0.0, lift + 0.3, 0.0)
    advance(simulation, robot, 1.5)
    z1 = supervisor.get_object(object_id).position[2]
    status = advance(simulation, robot, 1.0)
    z2 = supervisor.get_object(object_id).position[2]
    raised = min(z1, z2) - z0
    robot.magnet(False)
    advance(simulation, robot, 0.01)
    return raised, ("liftable" if raised >= 0.05 else "not_liftable"), status


def main():
    parser = argparse.ArgumentParser(
        prog="liftability.py",
        description="A few liftability trials in lock-step through the supervisor, against "
        "macsim --lockstep on worlds/affordance_trials.xml; prints a table.")
    parser.add_argument("--domain", type=int, required=True, help="DDS domain id, 0..232")
    parser.add_argument("--profile", help="Fast DDS XML profile file")
    parser.add_argument("--robot", default="kurt", help="robot namespace (default kurt)")
    parser.add_argument("--timeout", type=float, default=30.0,
                        help="s to wait for the simulator (default 30)")
    args = parser.parse_args()
    if not 0 <= args.domain <= 232 or not args.timeout > 0:
        parser.error("--domain is 0..232 and --timeout > 0")

    participant = macsim.Participant(domain=args.domain, profile=args.profile, name="liftability")
    simulation = macsim.Simulation(participant, timeout=args.timeout)
    supervisor = macsim.Supervisor(participant, timeout=args.timeout)
    robot = macsim.Robot(participant, args.robot)
    try:
        if "lockstep" not in simulation.features():
            print("liftability: this participant does not step on request", file=sys.stderr)
            return 2
        simulation.pause()
    except TimeoutError as error:
        print(f"liftability: {error}", file=sys.stderr)
        return 2

    # A command sent before the robot's reader matched this writer is lost: while paused, repeat
    # a harmless one until discovery settled (each trial's reset puts the robot back anyway).
    for _ in range(40):
        if robot.crane_connected:
            break
        time.sleep(0.05)
    for _ in range(10):
        robot.crane(0.0, 0.0, 0.0)
        time.sleep(0.02)

    print(f"{'object':<16} {'mass kg':>7} {'magnet.':>7} {'raised m':>9}  {'label':<13} "
          f"{'sim s':>6}  state hash")
    for name, shape, size, mass, magnetizable, color in TRIALS:
        raised, label, status = trial(simulation, supervisor, robot, name, shape, size, mass,
                                      magnetizable, color)
        print(f"{name:<16} {mass:>7.2f} {'yes' if magnetizable else 'no':>7} {raised:>9.3f}  "
              f"{label:<13} {status.sim_time:>6.2f}  {status.state_hash:016x}", flush=True)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
    except (TimeoutError, macsim.SupervisorError) as error:
        print(f"liftability: {error}", file=sys.stderr)
        sys.exit(1)
