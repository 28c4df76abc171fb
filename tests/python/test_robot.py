"""macsim.Robot against a real macsim: driving by odometry, the sensors, images and clouds as
numpy arrays, the crane and its magnet."""

import math
import time

import numpy as np
import pytest

import macsim
from conftest import start_macsim


@pytest.fixture
def robot(domain, spawn):
    start_macsim(spawn, domain, "worlds/small_room.xml", "--cameras", "320x240")
    participant = macsim.Participant(domain=domain, name="robot_test")
    kurt = macsim.Robot(participant, "kurt")
    kurt.odometry(timeout=20)
    return kurt


def wait_for(get, limit):
    """get() until it gives something (not empty, not None), for up to `limit` s."""
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline:
        value = get()
        if value is not None and len(value) > 0:
            return value
        time.sleep(0.05)
    raise AssertionError(f"nothing within {limit} s")


def turn_and_take_cloud(kurt):
    # Repeated: a command sent before the robot's reader matched this writer is lost.
    kurt.rotate_laser(3.0)
    try:
        return kurt.points(timeout=1.0)
    except TimeoutError:
        return None


def drive_until(kurt, linear, angular, done, limit=20.0):
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline:
        kurt.cmd_vel(linear, angular)
        odom = kurt.odometry(timeout=5)
        if done(odom):
            return odom
        time.sleep(0.02)
    raise AssertionError("the robot did not get there in time")


def test_drives_by_odometry_and_stops(robot):
    start = robot.odometry()
    # Odometry may come before this writer of cmd_vel is matched: each endpoint is discovered
    # on its own.
    deadline = time.monotonic() + 10
    while not robot.connected and time.monotonic() < deadline:
        time.sleep(0.02)
    assert robot.connected and robot.name == "kurt"
    end = drive_until(robot, 0.4, 0.0, lambda o: o.position[0] - start.position[0] > 0.5)
    assert abs(end.position[1] - start.position[1]) < 0.05 and abs(end.yaw) < 0.1
    assert end.linear_velocity[0] > 0.1 and end.stamp > start.stamp
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and abs(robot.odometry().linear_velocity[0]) > 0.005:
        robot.stop()
    assert abs(robot.odometry().linear_velocity[0]) < 0.005
    # Wheel speeds turn it on the spot: yaw grows counter-clockwise.
    yaw0 = robot.odometry().yaw
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and robot.odometry().yaw - yaw0 < 0.3:
        robot.wheel_speeds(-0.15, 0.15)
    assert robot.odometry().yaw - yaw0 >= 0.3
    robot.stop()


def test_sensors_come_as_python_values_and_arrays(robot):
    imu = robot.imu(timeout=5)
    assert abs(imu.yaw) < 0.1 and len(imu.orientation) == 4
    ranges = wait_for(robot.ranges, 10)  # the IR/sonar frames come at their own pace
    assert all(isinstance(v, float) for v in ranges.values())
    scan = robot.scan(timeout=5)
    assert scan.ranges.dtype == np.float32 and scan.ranges.ndim == 1
    expected = round((scan.angle_max - scan.angle_min) / scan.angle_increment) + 1
    assert abs(len(scan.ranges) - expected) <= 1
    later = robot.scan(after=scan.stamp, timeout=5)
    assert later.stamp > scan.stamp
    assert robot.scan(after=1e9) is None
    with pytest.raises(TimeoutError):
        robot.scan(after=1e9, timeout=0.2)
    points = wait_for(lambda: turn_and_take_cloud(robot), 20)
    assert points.dtype == np.float32 and points.ndim == 2 and points.shape[1] == 3
    assert points.shape[0] > 100 and np.isfinite(points).all()
    # The wall 4.5 m ahead is in the cloud.
    assert (np.abs(points[:, 0] - 4.45) < 0.1).sum() > 10
    robot.rotate_laser(0.0)


def test_images_are_numpy_arrays_that_change_when_the_robot_turns(robot):
    left = robot.image("left", timeout=10)
    assert left.shape == (240, 320, 3) and left.dtype == np.uint8
    assert not left.flags.writeable and not left.flags.owndata  # a view of the received sample
    assert left.std() > 5  # not a blank frame
    pair = robot.stereo(timeout=10)
    assert pair.left.shape == pair.right.shape == (240, 320, 3)
    assert pair.focal > 0 and pair.baseline > 0 and 0 < pair.cx < 320
    assert not np.array_equal(pair.left, pair.right)  # two eyes, two views
    with pytest.raises(ValueError):
        robot.image("middle")

    yaw0 = robot.odometry().yaw
    drive_until(robot, 0.0, 0.8, lambda o: o.yaw - yaw0 > math.pi / 2)
    robot.stop()
    turned = robot.image("left", after=robot.odometry().stamp, timeout=10)
    change = np.abs(turned.astype(np.int16) - left.astype(np.int16)).mean()
    assert change > 10, f"the view did not change: mean difference {change:.1f}"
    copy = turned.copy()
    copy[0, 0] = 255  # a copy is the user's to draw on
    assert copy.flags.writeable


def test_the_crane_and_its_magnet(robot):
    assert robot.crane_state(timeout=5) is not None
    deadline = time.monotonic() + 15
    state = robot.crane_state()
    while time.monotonic() < deadline:
        # Repeated: a command sent before the robot's reader matched this writer is lost.
        robot.crane(0.4, 0.2, 0.05)
        robot.magnet(True)
        assert robot.wait_delivered()
        state = robot.crane_state()
        if abs(state.slew - 0.4) < 0.02 and abs(state.lift - 0.2) < 0.02 and state.magnet_on:
            break
        time.sleep(0.05)
    assert state.slew == pytest.approx(0.4, abs=0.02)
    assert state.lift == pytest.approx(0.2, abs=0.02)
    assert state.hoist == pytest.approx(0.05, abs=0.01)
    assert state.magnet_on and state.held_object == ""


def test_the_kurt3d_description_gives_its_mounts_by_name():
    kurt = macsim.kurt3d_description()
    assert kurt["robot"] == "kurt3d"
    # base_link above the floor: the axles' height plus the wheels' radius (perimeter / 2 pi).
    assert kurt["base_height"] == pytest.approx(
        kurt["base_link_above_wheel_axle"] + kurt["wheel_perimeter"] / (2 * math.pi))
    assert kurt["wheel_radius"] * 2 * math.pi == pytest.approx(kurt["wheel_perimeter"])
    assert len(kurt["left_camera"]) == 3 and kurt["left_camera"][2] > kurt["pivot_height"]
    sensors = {k: v for k, v in kurt.items() if k.startswith("range_sensor ")}
    assert len(sensors) == 8
    x, y, yaw, sonar, low, high, fov = sensors["range_sensor ultrasound_front"]
    assert sonar == 1 and x > 0 and low < high
