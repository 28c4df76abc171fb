#!/usr/bin/env python3
"""rank_by_lift_model.py: what the KURT3D sees, ranked by a learned lift model.

Takes one stereo pair from the robot's cameras, finds the things in view with the trials' own
perception (macsim.affordances.objects_in_view), computes each one's lift features from the
cameras as a trial computes them, and prints them ranked by the model's P(liftable): the order
a controller would try them in. It moves nothing; against macsim --lockstep it steps the
simulator until a pair comes. The model must take only the cameras' features (it sees from
where it stands): affordance_learn --features hue (or camera) --save-model DIR.

    build/bin/affordance_trials --domain 7 --generator figure11 --trials 40 --out f11.csv
    build/bin/affordance_learn --in f11.csv --features hue --save-model models
    build/bin/macsim --world worlds/DemoWorld_figure11.xml --seed 2 --lockstep --domain 8 &
    PYTHONPATH=build/python python3 examples/python/rank_by_lift_model.py --domain 8 \\
        --model models/lift.yml --lockstep
"""

import argparse
import sys

try:
    import macsim
    from macsim import affordances
except ImportError as error:
    sys.exit(f"rank_by_lift_model: cannot import macsim ({error}): build the project and set "
             "PYTHONPATH=build/python")


def take_pair(robot, simulation, timeout):
    """The next stereo pair; in lock-step, stepped for until one comes (at most 2 s)."""
    if simulation is None:
        return robot.stereo(timeout=timeout)
    for _ in range(100):
        simulation.step(20)
        try:
            return robot.stereo(timeout=0.2)
        except TimeoutError:
            continue
    raise TimeoutError("no stereo pair in 2 s of sim time")


def rank(model, frame):
    """(P(liftable), box, features) of every thing in view, likeliest first."""
    ranked = []
    for box in affordances.objects_in_view(frame):
        seen = affordances.features("lift", frame, region=box)
        if seen["area_px"] == 0:  # not matched in the right image, or too small
            continue
        label, confidence = model.predict(seen)
        ranked.append((confidence if label == "liftable" else 1 - confidence, box, seen))
    ranked.sort(key=lambda entry: -entry[0])
    return ranked


def main():
    parser = argparse.ArgumentParser(
        prog="rank_by_lift_model.py",
        description="Ranks what the robot's cameras see by a learned lift model; moves nothing.")
    parser.add_argument("--domain", type=int, required=True, help="DDS domain id, 0..232")
    parser.add_argument("--profile", help="Fast DDS XML profile file")
    parser.add_argument("--robot", default="kurt", help="robot namespace (default kurt)")
    parser.add_argument("--model", required=True,
                        help="a lift model on the cameras' features (affordance_learn "
                        "--features hue --save-model DIR writes DIR/lift.yml)")
    parser.add_argument("--lockstep", action="store_true",
                        help="step the simulator until a stereo pair comes (macsim --lockstep)")
    parser.add_argument("--timeout", type=float, default=20.0,
                        help="s to wait for the robot (default 20)")
    args = parser.parse_args()
    if not 0 <= args.domain <= 232 or not args.timeout > 0:
        parser.error("--domain is 0..232 and --timeout > 0")
    try:
        model = affordances.load(args.model)
    except affordances.AffordanceModelError as error:
        parser.error(str(error))
    if model.affordance != "lift" or "liftable" not in model.labels:
        parser.error(f"{args.model} is a model of {model.affordance}, not lift")
    camera = set(affordances.feature_group("camera"))
    if not set(model.features) <= camera:
        parser.error(f"{args.model} takes {sorted(set(model.features) - camera)}, which the "
                     "cameras do not give: train with --features hue (or camera)")

    participant = macsim.Participant(domain=args.domain, profile=args.profile,
                                     name="rank_by_lift_model")
    robot = macsim.Robot(participant, args.robot)
    simulation = macsim.Simulation(participant, timeout=args.timeout) if args.lockstep else None
    if simulation is not None and "lockstep" not in simulation.features():
        print("rank_by_lift_model: this participant does not step on request", file=sys.stderr)
        return 2
    frame = take_pair(robot, simulation, args.timeout)
    ranked = rank(model, frame)
    print(f"rank_by_lift_model: {len(ranked)} thing(s) in view, by the lift model "
          f"({model.rows} rows of {model.generator}, held-out accuracy "
          f"{100 * model.held_out_accuracy:.1f} %):")
    for place, (p, (x, y, w, h), seen) in enumerate(ranked, 1):
        where = (f"{seen['stereo_range']:.2f} m away" if seen["stereo_range"] > 0
                 else "range unknown")
        print(f"  {place}. P(liftable) {p:.2f}  hue {seen['hue']:5.1f}  box {x},{y} {w}x{h}  "
              f"{where}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
    except TimeoutError as error:
        print(f"rank_by_lift_model: {error}", file=sys.stderr)
        sys.exit(3)
