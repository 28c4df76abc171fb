"""Learned affordance models (affordance_learn --save-model DIR writes DIR/<affordance>.yml).

    from macsim import affordances
    lift = affordances.load("models/lift.yml")
    seen = affordances.features("lift", robot.stereo(), robot.scan())   # the trials' perception
    label, confidence = lift.predict(seen)
    found = affordances.plan("effects/effects.ppddl", "problems/scene-1.pddl")  # kurt_plan's planner

A model refuses a missing or damaged file, another format version, features other than the
ones asked for, and values that are not finite, with AffordanceModelError naming the file or
the feature.
"""

from os import PathLike
from typing import Optional, Sequence, Union

from ._macsim import AffordanceModel, AffordanceModelError, PddlError
from ._macsim import plan_files
from ._macsim import affordance_feature_group as feature_group
from ._macsim import affordance_features as features
from ._macsim import objects_in_view
from ._macsim import load_sensor_inputs as load_inputs

__all__ = ["AffordanceModel", "AffordanceModelError", "PddlError", "feature_group", "features",
           "load", "load_inputs", "objects_in_view", "plan"]


def plan(domain: Union[str, PathLike], problem: Union[str, PathLike]) -> dict:
    """Plans for a PDDL problem file (kurt_plan --problems DIR writes the scenes it perceived)
    over a domain file (learn_effects' effects.ppddl, or the hand-written one) with kurt_plan's
    planner: {'reached', 'steps': [(text, probability, added, removed)], 'probability',
    'reason', 'seconds'}. PddlError (a ValueError) names the file and line of a fault."""
    return plan_files(str(domain), str(problem))


def load(path: Union[str, PathLike], features: Optional[Sequence[str]] = None) -> AffordanceModel:
    """The model in `path`; with `features`, refused unless it takes exactly those, in order."""
    return AffordanceModel.load(str(path), list(features or []))
