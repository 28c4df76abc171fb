"""macsim.affordances from Python: a model affordance_learn saved from the committed trial rows
loads, answers as the C++ model does (its label and the share of trees that voted for it), and
every bad file or bad feature is refused with AffordanceModelError naming the file or feature."""

import csv
import math
import subprocess

import pytest

import macsim
from macsim import affordances
from conftest import binary, source

ROWS = source("tests/tools/affordances/lift_trials.csv")


@pytest.fixture(scope="module")
def lift_model(tmp_path_factory):
    directory = tmp_path_factory.mktemp("models")
    result = subprocess.run([binary("affordance_learn"), "--in", ROWS, "--save-model",
                             str(directory)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    return directory / "lift.yml"


def rows():
    with open(ROWS) as f:
        return list(csv.DictReader(f))


def test_a_saved_model_loads_and_ranks_what_the_robot_saw(lift_model):
    model = affordances.load(lift_model)
    assert model.affordance == "lift"
    assert model.labels == ["liftable", "not_liftable"]
    assert model.features[:4] == ["r", "g", "b", "hue"]
    assert model.rows == 300 and model.seeds == "1-300" and model.generator == "material"
    assert 0.95 <= model.held_out_accuracy <= 1
    right = 0
    for row in rows():
        by_name = {name: float(row[name]) for name in model.features}
        label, confidence = model.predict(by_name)
        assert 0.5 <= confidence <= 1
        # the same answer from a sequence in the model's order
        assert model.predict([by_name[n] for n in model.features]) == (label, confidence)
        right += label == row["label"]
    assert right >= 290  # refit on these very rows


def test_the_features_a_controller_computes_must_be_the_models(lift_model):
    model = affordances.load(lift_model, features=affordances.load(lift_model).features)
    with pytest.raises(affordances.AffordanceModelError, match=r"lift.yml: the model takes"):
        affordances.load(lift_model, features=["hue", "width_m"])
    values = [1.0] * len(model.features)
    for bad in (math.nan, math.inf, -1e308):
        values[3] = bad
        with pytest.raises(macsim.AffordanceModelError, match="feature hue"):
            model.predict(values)
    with pytest.raises(ValueError, match="no value for feature r"):
        model.predict({"g": 1.0})


def test_a_sensors_feature_group_names_the_features_it_gives(lift_model):
    camera = affordances.feature_group("camera")
    assert camera[:4] == ["r", "g", "b", "hue"] and "stereo_range" in camera
    cloud = affordances.feature_group("cloud")
    assert "cell_0_0_near" in cloud and "hue" not in cloud and "corridor_height" not in cloud
    shape = affordances.feature_group("shape")
    assert "corridor_height" in shape and "shape_recess_max" in shape and "cell_0_0_near" not in shape
    # The lift model of the committed rows takes the camera's and the sweep's features.
    model = affordances.load(lift_model)
    assert set(model.features) == set(camera) | set(affordances.feature_group("sweep"))
    with pytest.raises(ValueError, match="no feature group 'radar'"):
        affordances.feature_group("radar")


def test_bad_files_are_refused_naming_them(lift_model, tmp_path):
    with pytest.raises(affordances.AffordanceModelError, match="absent.yml: no such model file"):
        affordances.load(tmp_path / "absent.yml")
    cut = tmp_path / "cut.yml"
    cut.write_text(lift_model.read_text()[:5000])
    with pytest.raises(affordances.AffordanceModelError, match="cut.yml: damaged"):
        affordances.load(cut)
    newer = tmp_path / "newer.yml"
    newer.write_text(lift_model.read_text().replace("format_version: 1", "format_version: 7"))
    with pytest.raises(affordances.AffordanceModelError, match="format version 7"):
        affordances.load(newer)


def test_python_computes_a_trials_row_from_what_the_trial_saw(domain, tmp_path):
    # The one perception from Python: affordance_trials keeps what each trial perceived from;
    # macsim.affordances.features on it gives the row the trial wrote, to its last %.9g digit.
    for affordance, generator in (("lift", "material"), ("traverse", "balanced")):
        out = tmp_path / f"{affordance}.csv"
        result = subprocess.run(
            [binary("affordance_trials"), "--domain", str(domain), "--affordance", affordance,
             "--generator", generator, "--seed", "11", "--trials", "1", "--out", str(out),
             "--keep-inputs", str(tmp_path / "inputs"), "--logs", str(tmp_path / "logs")],
            capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, result.stdout + result.stderr
        with open(out) as f:
            (row,) = list(csv.DictReader(f))
        frame, scan, points = affordances.load_inputs(str(tmp_path / "inputs"),
                                                      f"{affordance}_{row['seed']}")
        assert (points is not None) == (affordance == "traverse")
        features = affordances.features(affordance, frame, scan, points)
        assert len(features) == (14 if affordance == "lift" else 14 + 240 + 3 + 6)
        for name, value in features.items():
            assert "%.9g" % value == row[name], (affordance, name)
    with pytest.raises(ValueError, match="absent.yml.gz: no such file"):
        affordances.load_inputs(str(tmp_path), "absent")
    with pytest.raises(ValueError, match="no affordance 'fly'"):
        affordances.features("fly")


ROOM = source("affordances/domains/kurt3d_room_by_hand.pddl")


def write_problem(path, init, goal):
    path.write_text("(define (problem p)\n  (:domain kurt3d-room)\n"
                    "  (:objects start - place switch - switch door - door red_1 blue_1 - thing)\n"
                    f"  (:init {init})\n  (:goal {goal}))\n")
    return path


def test_python_plans_a_scene_with_kurt_plans_planner(tmp_path):
    scene = write_problem(tmp_path / "scene.pddl",
                          "(robot-at start) (hand-free) (opens switch door) (tried blue_1)",
                          "(beyond door)")
    found = affordances.plan(ROOM, scene)
    assert found["reached"], found["reason"]
    assert [s[0] for s in found["steps"]] == [
        "(go start red_1)", "(lift red_1)", "(go red_1 switch)", "(put-down red_1 switch door)",
        "(go switch door)", "(drive-through door)"]
    text, probability, added, removed = found["steps"][1]
    assert probability == 0.5 and "(holding red_1)" in added and "(hand-free)" in removed
    assert math.isclose(found["probability"], 0.5 * 0.8)
    # Every thing tried and none held: no plan, and why.
    stuck = write_problem(tmp_path / "stuck.pddl",
                          "(robot-at start) (hand-free) (opens switch door) (tried red_1) "
                          "(tried blue_1)", "(beyond door)")
    none = affordances.plan(ROOM, stuck)
    assert not none["reached"] and none["steps"] == []
    assert "cannot be reached" in none["reason"]


def test_a_bad_problem_is_refused_naming_its_line(tmp_path):
    bad = write_problem(tmp_path / "bad.pddl", "(robot-at nowhere)", "(beyond door)")
    with pytest.raises(affordances.PddlError, match=r"bad.pddl:4: unknown object 'nowhere'"):
        affordances.plan(ROOM, bad)
    with pytest.raises(ValueError, match="cannot be read"):
        affordances.plan(tmp_path / "none.pddl", bad)
