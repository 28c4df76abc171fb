#!/usr/bin/env python3
"""Records tests/sessions/supervised_demo_world.session: macsim in lock-step on the
demonstrator's room, the robot driven while a supervisor creates, changes, moves and destroys
objects, triggers the door's switch and moves its leaf, and saves and restores a snapshot. The file
is a fixture: a build after it must replay it to every hash (SessionFixture in
tests/integration/session_replay_test.cpp). Run from the source tree with a build's programs:

    python3 tests/sessions/record_fixture.py build [domain]

Paths in the session are the repository's relative ones (macsim runs in the source tree); a
supervisor import would be recorded by its absolute path, so there is none."""

import math
import os
import subprocess
import sys
import time

build = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build")
domain = int(sys.argv[2]) if len(sys.argv) > 2 else 97
root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(build, "python"))
import macsim  # noqa: E402

out = "tests/sessions/supervised_demo_world.session"
env = dict(os.environ, FASTRTPS_DEFAULT_PROFILES_FILE=os.path.join(root, "deploy/dds/localhost.xml"))
sim = subprocess.Popen([os.path.join(build, "bin/macsim"), "--world", "worlds/DemoWorld_v1.xml",
                        "--domain", str(domain), "--lockstep", "--cameras", "off",
                        "--record-session", out, "--session-hash-every", "10"],
                       cwd=root, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
try:
    participant = macsim.Participant(domain=domain, name="session_fixture")
    s, simulation = macsim.Supervisor(participant), macsim.Simulation(participant)
    robot = macsim.Robot(participant, "kurt", lockstep=True)
    simulation.step(10)
    box = macsim.Component(macsim.SHAPE_BOX, (0.1, 0.1, 0.1), color=(0.2, 0.9, 0.2, 1.0))
    oid = s.create_object("fixture_box", [box], position=(-0.5, 0.3, 0.05), mass=0.2)
    robot.cmd_vel(0.2, 0.3)
    simulation.step(100)
    s.set_pose(oid, (-0.5, -0.6, 0.05), (0, 0, math.sin(0.25), math.cos(0.25)))
    s.set_box_size(oid, 0, (0.1, 0.1, 0.08))
    s.set_color(oid, (0.1, 0.2, 0.3, 1.0))
    s.set_density(oid, 300.0)
    s.set_linear_velocity(oid, (0.1, 0, 0))
    s.add_force(oid, (0, 0, 1))
    simulation.step(50)
    can = s.create_object("fixture_can", [macsim.Component(macsim.SHAPE_CYLINDER, (0.05, 0, 0.1))],
                          position=(-1.5, 1.5, 0.07))
    s.set_cylinder_size(can, 0, 0.04, 0.12)
    s.set_user_data(can, "fixture")
    ball = s.find_object("environment_01/ball_green")
    s.set_density(ball, 450.0)
    s.add_force(ball, (0.0, 3.0, 8.0))
    robot.cmd_vel(0.1, -0.2)
    simulation.step(100)
    s.set_switch_triggered(0, True)
    simulation.step(200)
    door = s.get_door(0)
    leaf = s.get_object(door.object_ids[0]).position
    s.set_door_position(0, (leaf[0], leaf[1] - 0.5, leaf[2]))
    s.save_snapshot("fixture")
    simulation.step(100)
    s.restore_snapshot("fixture")
    s.destroy_object(oid)
    s.destroy_by_user_data("fixture")
    robot.stop()
    simulation.step(100)
    print("state hash", hex(simulation.status().state_hash))
finally:
    sim.terminate()
    print(sim.communicate(timeout=30)[0])
