"""The Python examples as a user runs them: hello_kurt.py against macsim and against the real
robot's side (kurt_adapter with the KURT emulator), liftability.py against macsim --lockstep,
rank_by_lift_model.py with a model learned from Figure 11 trials, plan_scene.py on problem files."""

import os
import subprocess
import sys

from conftest import binary, source, start_macsim

HELLO = source("examples/python/hello_kurt.py")
LIFTABILITY = source("examples/python/liftability.py")
RANK = source("examples/python/rank_by_lift_model.py")


def run(argv, timeout=120):
    return subprocess.run([sys.executable, *argv], capture_output=True, text=True,
                          timeout=timeout, env=os.environ.copy())


def test_hello_kurt_reaches_its_goal_on_the_simulator(domain, spawn):
    start_macsim(spawn, domain, "worlds/small_room.xml", "--cameras", "off")
    done = run([HELLO, "--domain", str(domain), "--distance", "0.5"])
    assert done.returncode == 0, done.stdout + done.stderr
    travelled = float(done.stdout.split("arrived: travelled ")[1].split()[0])
    assert abs(travelled - 0.5) < 0.02, done.stdout


def test_hello_kurt_reaches_its_goal_on_the_real_robot_side(domain, spawn):
    port = 5000 + 2 * domain  # a userspace CAN bus on two loopback ports
    emulator = spawn([binary("kurt_emulator"), "--can", f"udp:{port}:{port + 1}"])
    assert emulator.wait_for_output("kurt_emulator: on", 10), emulator.output()
    adapter = spawn([binary("kurt_adapter"), "--can", f"udp:{port + 1}:{port}",
                     "--domain", domain])
    assert adapter.wait_for_output("rt/kurt/imu", 20), adapter.output()
    done = run([HELLO, "--domain", str(domain), "--distance", "0.3"])
    assert done.returncode == 0, done.stdout + done.stderr + adapter.output()
    assert "arrived" in done.stdout


def test_hello_kurt_exit_codes_without_a_robot(domain):
    assert run([HELLO, "--help"]).returncode == 0
    assert run([HELLO]).returncode == 2  # --domain is required: no default domain
    assert run([HELLO, "--domain", "7", "--speed", "-1"]).returncode == 2
    nobody = run([HELLO, "--domain", str(domain), "--discovery-timeout", "1"])
    assert nobody.returncode == 2
    assert f"domain {domain}" in nobody.stderr


def test_liftability_trials_print_their_table(domain, spawn):
    assert run([LIFTABILITY, "--help"]).returncode == 0
    start_macsim(spawn, domain, "worlds/affordance_trials.xml", "--lockstep", "--cameras", "off")
    done = run([LIFTABILITY, "--domain", str(domain)], timeout=240)
    assert done.returncode == 0, done.stdout + done.stderr
    rows = {line.split()[0]: line.split() for line in done.stdout.splitlines()[1:]}
    assert rows["light_iron_box"][4] == "liftable", done.stdout
    assert rows["light_wood_box"][4] == "not_liftable", done.stdout
    assert rows["heavy_iron_box"][4] == "not_liftable", done.stdout
    assert len(rows) == 4


def test_rank_by_lift_model_ranks_what_the_cameras_see_heavy_blue_last(domain, spawn, tmp_path):
    assert run([RANK, "--help"]).returncode == 0
    rows, models = tmp_path / "figure11.csv", tmp_path / "models"
    for argv in ([binary("affordance_trials"), "--domain", str(domain), "--generator", "figure11",
                  "--trials", "24", "--out", str(rows)],
                 [binary("affordance_learn"), "--in", str(rows), "--features", "hue",
                  "--save-model", str(models)]):
        made = subprocess.run(argv, capture_output=True, text=True, timeout=180)
        assert made.returncode == 0, made.stdout + made.stderr
    # A model of features the cameras do not give is refused before anything is asked.
    wrong = run([RANK, "--domain", str(domain), "--model",
                 source("tests/tools/affordances/lift_trials.csv")])
    assert wrong.returncode == 2, wrong.stdout + wrong.stderr
    start_macsim(spawn, domain, "worlds/DemoWorld_figure11.xml", "--seed", "2", "--lockstep")
    done = run([RANK, "--domain", str(domain), "--model", str(models / "lift.yml"), "--lockstep"])
    assert done.returncode == 0, done.stdout + done.stderr
    ranked = [line.split() for line in done.stdout.splitlines() if "P(liftable)" in line]
    assert ranked, done.stdout
    chances = [float(words[2]) for words in ranked]
    hues = [float(words[4]) for words in ranked]
    assert chances == sorted(chances, reverse=True), done.stdout
    # The blue (lead) cans in view are judged heavy, the others light.
    blue = [p for p, hue in zip(chances, hues) if 200 <= hue <= 260]
    assert blue and max(blue) < 0.5, done.stdout


PLAN_SCENE = source("examples/python/plan_scene.py")


def test_plan_scene_plans_a_problem_file_and_names_a_bad_one(tmp_path):
    room = source("affordances/domains/kurt3d_room_by_hand.pddl")
    scene = tmp_path / "scene-1.pddl"
    scene.write_text("(define (problem scene-1)\n  (:domain kurt3d-room)\n"
                     "  (:objects start - place switch - switch door - door)\n"
                     "  (:init (robot-at start) (hand-free) (open door))\n"
                     "  (:goal (beyond door)))\n")
    result = run([PLAN_SCENE, room, str(scene)])
    assert result.returncode == 0, result.stdout + result.stderr
    assert "2 step(s)" in result.stdout
    assert "1. (go start door) -> (robot-at door); not (robot-at start) (p = 1.00)" in result.stdout
    assert "2. (drive-through door) -> (beyond door)" in result.stdout
    scene.write_text(scene.read_text().replace("(open door)", "(open wall)"))
    bad = run([PLAN_SCENE, room, str(scene)])
    assert bad.returncode == 2
    assert "scene-1.pddl:4: unknown object 'wall'" in bad.stderr
