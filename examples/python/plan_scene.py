#!/usr/bin/env python3
"""Plans a perceived scene again from Python, with kurt_plan's planner.

kurt_plan --problems DIR writes each planning round's scene as a PDDL problem (scene-N.pddl).
This plans one of them over a domain (learn_effects' DIR/effects.ppddl, or the hand-written
affordances/domains/kurt3d_room_by_hand.pddl) and prints the plan with each step's predicted
effect and probability, or why there is none. It moves nothing.

    PYTHONPATH=build/python python3 examples/python/plan_scene.py DOMAIN PROBLEM
Exit 0 with a plan, 1 without, 2 on a bad file (named with its line).
"""

import argparse
import sys

from macsim import affordances


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("domain", help="a PDDL domain file (STRIPS or PPDDL)")
    parser.add_argument("problem", help="a PDDL problem file of that domain")
    args = parser.parse_args()
    try:
        found = affordances.plan(args.domain, args.problem)
    except ValueError as error:  # PddlError, or a file that cannot be read
        print(f"plan_scene: {error}", file=sys.stderr)
        return 2
    if not found["reached"]:
        print(f"plan_scene: no plan: {found['reason']}")
        return 1
    print(f"plan_scene: {len(found['steps'])} step(s), probability {found['probability']:.3f}, "
          f"planned in {1e3 * found['seconds']:.2f} ms")
    for i, (step, probability, added, removed) in enumerate(found["steps"], 1):
        effect = " ".join(added) + ("; not " + " ".join(removed) if removed else "")
        print(f"  {i}. {step} -> {effect} (p = {probability:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
