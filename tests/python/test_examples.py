"""The Python examples as a user runs them: hello_kurt.py against macsim and against the real
robot's side (kurt_adapter with the KURT emulator), liftability.py against macsim --lockstep."""

import os
import subprocess
import sys

from conftest import binary, source, start_macsim

HELLO = source("examples/python/hello_kurt.py")
LIFTABILITY = source("examples/python/liftability.py")


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
