"""Learned affordance models (affordance_learn --save-model DIR writes DIR/<affordance>.yml).

    from macsim import affordances
    lift = affordances.load("models/lift.yml")
    seen = affordances.features("lift", robot.stereo(), robot.scan())   # the trials' perception
    label, confidence = lift.predict(seen)

A model refuses a missing or damaged file, another format version, features other than the
ones asked for, and values that are not finite, with AffordanceModelError naming the file or
the feature.
"""

from os import PathLike
from typing import Optional, Sequence, Union

from ._macsim import AffordanceModel, AffordanceModelError
from ._macsim import affordance_feature_group as feature_group
from ._macsim import affordance_features as features
from ._macsim import objects_in_view
from ._macsim import load_sensor_inputs as load_inputs

__all__ = ["AffordanceModel", "AffordanceModelError", "feature_group", "features", "load",
           "load_inputs", "objects_in_view"]


def load(path: Union[str, PathLike], features: Optional[Sequence[str]] = None) -> AffordanceModel:
    """The model in `path`; with `features`, refused unless it takes exactly those, in order."""
    return AffordanceModel.load(str(path), list(features or []))
