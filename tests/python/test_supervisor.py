"""Every supervisor call of macsim.Supervisor against a real macsim (lock-step, so nothing moves
unless stepped), and the errors: refusals as SupervisorError with their code, hostile numbers
refused, a silent simulator a TimeoutError."""

import math
import re
import time

import pytest

import macsim
from conftest import binary, source, start_macsim


@pytest.fixture
def world(domain, spawn):
    start_macsim(spawn, domain, "worlds/small_room.xml", "--lockstep", "--cameras", "off")
    participant = macsim.Participant(domain=domain, name="supervisor_test")
    return participant, macsim.Supervisor(participant), macsim.Simulation(participant)


def box(size=0.1, color=(0.2, 0.9, 0.2, 1.0)):
    return macsim.Component(macsim.SHAPE_BOX, (size, size, size), color=color)


def test_objects_are_listed_found_and_read(world):
    _, supervisor, _ = world
    objects = supervisor.list_objects()
    assert "red_box" in objects.values() and "wall_ahead" in objects.values()
    red = supervisor.find_object("red_box")
    assert objects[red] == "red_box"
    got = supervisor.get_object(red)
    assert (got.id, got.name, got.portable) == (red, "red_box", True)
    assert got.position == pytest.approx((1.0, 1.0, 0.1), abs=0.01)
    assert got.components[0].shape == macsim.SHAPE_BOX
    assert got.components[0].size == pytest.approx((0.2, 0.2, 0.2))
    assert got.mass == pytest.approx(100 * 0.2 ** 3)
    assert supervisor.get_object(supervisor.find_object("wall_ahead")).portable is False


def test_an_object_is_created_changed_and_destroyed(world):
    _, s, _ = world
    oid = s.create_object("py_box", [box()], position=(-0.5, 0.3, 0.05), mass=0.2)
    o = s.get_object(oid)
    assert o.name == "py_box" and o.kind == macsim.KIND_OBJECT
    assert o.mass == pytest.approx(0.2) and o.components[0].color[1] == pytest.approx(0.9)

    s.set_pose(oid, (-0.5, -0.6, 0.05), (0, 0, math.sin(0.25), math.cos(0.25)))
    assert s.get_object(oid).position == pytest.approx((-0.5, -0.6, 0.05))
    s.set_position(oid, (-0.7, -0.6, 0.05))
    s.set_orientation(oid, (0, 0, 0, 1))
    o = s.get_object(oid)
    assert o.position == pytest.approx((-0.7, -0.6, 0.05)) and o.orientation[3] == pytest.approx(1)
    s.set_box_size(oid, 0, (0.1, 0.1, 0.08))
    assert s.get_object(oid).components[0].size == pytest.approx((0.1, 0.1, 0.08))
    s.set_color(oid, (0.1, 0.2, 0.3, 1.0))
    assert s.get_object(oid).components[0].color == pytest.approx((0.1, 0.2, 0.3, 1.0))
    texture = source("worlds/DemoEnvironment_v1/textures/checker.bmp")
    s.set_texture(oid, texture)
    assert s.get_object(oid).components[0].texture.endswith("checker.bmp")
    s.set_texture(oid, "")
    assert s.get_object(oid).components[0].texture == ""
    s.set_mass(oid, 0.5)
    assert s.get_object(oid).mass == pytest.approx(0.5)
    s.set_density(oid, 300.0)
    assert s.get_object(oid).density == pytest.approx(300.0)
    s.set_linear_velocity(oid, (0.1, 0, 0))
    s.set_angular_velocity(oid, (0, 0, 0.5))
    o = s.get_object(oid)
    assert o.linear_velocity == pytest.approx((0.1, 0, 0)) and o.angular_velocity[2] == pytest.approx(0.5)
    s.add_force(oid, (0, 0, 1))
    s.add_torque(oid, (0, 0, 0.01))
    s.set_frozen(oid, True)
    assert s.get_object(oid).frozen
    s.set_frozen(oid, False)
    s.set_magnetizable(oid, True)
    assert s.get_object(oid).magnetizable
    s.set_user_data(oid, "python-test")
    assert s.find_by_user_data("python-test") == [oid]
    s.set_user_labels(oid, 3, 4)
    o = s.get_object(oid)
    assert (o.user_data, o.user_color, o.user_shape) == ("python-test", 3, 4)
    s.destroy_object(oid)
    assert oid not in s.list_objects()
    with pytest.raises(macsim.SupervisorError) as error:
        s.get_object(oid)
    assert error.value.code == macsim.ERR_UNKNOWN_OBJECT


def test_shapes_ramps_and_imports(world):
    _, s, _ = world
    can = s.create_object("py_can", [macsim.Component(macsim.SHAPE_CYLINDER, (0.05, 0, 0.1))],
                          position=(-1.5, 1.5, 0.07))
    s.set_cylinder_size(can, 0, 0.04, 0.12)
    assert s.get_object(can).components[0].size == pytest.approx((0.04, 0, 0.12))
    ball = s.create_object("py_ball", [macsim.Component(macsim.SHAPE_SPHERE, (0.05, 0, 0))],
                           position=(-1.5, -1.5, 0.07))
    s.set_sphere_size(ball, 0, 0.06)
    assert s.get_object(ball).components[0].size[0] == pytest.approx(0.06)
    ramp = s.create_object("py_ramp", kind=macsim.KIND_RAMP, position=(-2, 0, 0),
                           ramp=(0.5, 0.1, 0.2), portable=False)
    assert s.get_object(ramp).ramp == pytest.approx((0.5, 0.1, 0.2))
    s.set_ramp(ramp, 0.6, 0.12, 0.25)
    assert s.get_object(ramp).ramp == pytest.approx((0.6, 0.12, 0.25))
    with pytest.raises(macsim.SupervisorError) as error:
        s.set_sphere_size(can, 0, 0.1)
    assert error.value.code == macsim.ERR_WRONG_GEOMETRY

    assert s.door_count() == 0
    s.import_environment(source("worlds/DemoEnvironment_v1/materials.xml"), "materials")
    ids = s.import_environment(source("worlds/DemoEnvironment_v1/doors/door_switch.xml"),
                               "py_door", (-3, -3, 0))
    assert len(ids) >= 4
    assert s.door_count() == 1
    door = s.get_door(0)
    assert door.name and not door.triggered and door.gap == macsim.GAP_CLOSED
    assert len(door.object_ids) == 4 and set(door.object_ids) <= set(ids)
    s.set_switch_triggered(0, True)
    assert s.get_door(0).virtually_triggered
    leaf = s.get_object(door.object_ids[0]).position
    s.set_door_position(0, (leaf[0], leaf[1] - 0.5, leaf[2]))
    assert s.get_object(door.object_ids[0]).position[1] == pytest.approx(leaf[1] - 0.5, abs=1e-6)
    platform = s.get_object(door.object_ids[2]).position
    s.set_switch_position(0, (platform[0] + 0.3, platform[1], platform[2]))
    assert s.get_object(door.object_ids[2]).position[0] == pytest.approx(platform[0] + 0.3, abs=1e-6)

    s.set_user_data(can, "py")
    s.set_user_data(ball, "py")
    assert s.destroy_by_user_data("py") == 2
    portable = sum(1 for oid in s.list_objects() if s.get_object(oid).portable)
    assert s.destroy_all(macsim.DESTROY_PORTABLE_OBJECTS) >= portable > 0
    assert all(not s.get_object(oid).portable for oid in s.list_objects())


def test_snapshots_reset_and_the_state_hash(world):
    _, s, simulation = world
    red = s.find_object("red_box")
    before = s.state_hash()
    s.save_snapshot("start")
    s.set_position(red, (1.5, 1.0, 0.1))
    moved = s.state_hash()
    assert moved != before
    s.restore_snapshot("start")
    assert s.state_hash() == before
    with pytest.raises(macsim.SupervisorError):
        s.restore_snapshot("never_saved")
    s.set_position(red, (1.5, 1.0, 0.1))
    simulation.step(10)
    s.reset(macsim.RESET_EVERYTHING)
    assert s.get_object(red).position == pytest.approx((1.0, 1.0, 0.1), abs=0.01)
    assert s.state_hash() == before


def test_refusals_carry_their_code_and_leave_the_world_as_it_was(world):
    _, s, _ = world
    red = s.find_object("red_box")
    before = s.state_hash()
    for hostile in (math.nan, math.inf, -1.0, 1e308):
        with pytest.raises(macsim.SupervisorError) as error:
            s.set_mass(red, hostile)
        assert error.value.code == macsim.ERR_INVALID_ARGUMENT, hostile
    with pytest.raises(macsim.SupervisorError) as error:
        s.set_position(red, (math.nan, 0, 0))
    assert error.value.code == macsim.ERR_INVALID_ARGUMENT
    # Into the wall: refused, and the reply names what it would penetrate.
    wall = s.get_object(s.find_object("wall_ahead")).position
    with pytest.raises(macsim.SupervisorError) as error:
        s.set_position(red, wall)
    assert error.value.code == macsim.ERR_PENETRATION
    assert "wall_ahead" in error.value.names
    assert isinstance(error.value, RuntimeError) and "code 5" in str(error.value)
    with pytest.raises(macsim.SupervisorError) as error:
        s.find_object("no_such_object")
    assert error.value.code == macsim.ERR_UNKNOWN_OBJECT
    with pytest.raises(macsim.SupervisorError) as error:
        s.set_texture(red, source("worlds/no_such_picture.bmp"))
    assert error.value.code == macsim.ERR_BAD_TEXTURE
    # Outside the data roots: refused as a file, whether it exists or not.
    for outside in ("/nonexistent/picture.bmp", "/etc/hostname"):
        with pytest.raises(macsim.SupervisorError, match="is outside the folders") as error:
            s.set_texture(red, outside)
        assert error.value.code == macsim.ERR_BAD_FILE
    with pytest.raises(macsim.SupervisorError) as error:
        s.get_door(7)
    assert s.state_hash() == before
    # Bad arguments never leave Python.
    with pytest.raises(TypeError):
        s.set_position(red, (1, 2))
    with pytest.raises(ValueError):
        macsim.Component(9, (1, 1, 1))
    with pytest.raises(ValueError):
        macsim.Component(macsim.SHAPE_BOX, (1, 1))
    with pytest.raises(ValueError):
        s.timeout = -1
        s.state_hash()


def test_the_world_state_is_a_dict_of_objects_by_id(world):
    participant, s, simulation = world
    state = macsim.WorldState(participant)
    red = s.find_object("red_box")
    simulation.step(100)  # the state goes out every 0.1 s of sim time
    objects = state.wait(lambda objects: red in objects, timeout=20)
    assert objects[red].name == "red_box"
    assert set(objects) == set(s.list_objects())
    created = s.create_object("late_box", [box()], position=(-0.5, -1.5, 0.05))
    simulation.step(100)
    assert state.wait(lambda objects: created in objects, timeout=20)[created].name == "late_box"
    s.destroy_object(created)
    simulation.step(100)
    assert created not in state.wait(lambda objects: created not in objects, timeout=20)
    with pytest.raises(TimeoutError):
        state.wait(lambda objects: False, timeout=0.2)


def test_a_missing_simulator_is_a_timeout_not_a_hang(domain):
    participant = macsim.Participant(domain=domain)
    supervisor = macsim.Supervisor(participant, timeout=0.5)
    with pytest.raises(TimeoutError, match=f"domain {domain}"):
        supervisor.state_hash()
    with pytest.raises(TimeoutError):
        macsim.Simulation(participant, timeout=0.3).step(1)
    with pytest.raises(ValueError):
        macsim.Participant(domain=233)


def rss_kib(process):
    """The resident memory of a started process (VmRSS), KiB."""
    with open(f"/proc/{process.proc.pid}/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS")


def demo_world(domain, spawn, *options):
    """macsim on the demo world after 4 s of its laser turning: its state holds a 3D sweep."""
    process = start_macsim(spawn, domain, "worlds/DemoWorld_v1.xml", "--lockstep", "--cameras",
                           "off", *options)
    participant = macsim.Participant(domain=domain, name="snapshot_cap_test")
    # Steps of the demo world with its sweep take a while on a loaded machine: none of these is
    # meant to be quick, so none is given up as busy after the default 10 s.
    robot, simulation = macsim.Robot(participant), macsim.Simulation(participant, timeout=300)
    for _ in range(40):  # repeated: a command sent before the robot's reader matched is lost
        robot.rotate_laser(1.0)
        robot.wait_delivered()
        simulation.step(500)
        try:
            robot.points(timeout=0.5)
            break
        except TimeoutError:
            pass
    else:
        raise AssertionError("the laser never turned")
    simulation.step(4000)
    return process, macsim.Supervisor(participant), participant


# A snapshot of the demo world with a laser sweep is about 540 KB; macsim's resident memory may
# move by this much besides what it keeps of them (allocator, DDS buffers of the requests).
SNAPSHOT_KIB = 600
MARGIN_KIB = 24 * 1024


def test_snapshots_past_the_cap_are_refused_and_keep_memory_within_the_budget(domain, spawn):
    cap = 10
    process, s, _ = demo_world(domain, spawn, "--max-snapshots", str(cap))
    s.save_snapshot("warm_up")  # the first reply's buffers are not the snapshots' doing
    s.delete_snapshot("warm_up")
    before = rss_kib(process)
    refused = []
    for i in range(cap + 100):
        try:
            s.save_snapshot(f"client_{i}")
        except macsim.SupervisorError as error:
            refused.append((i, error))
    assert [i for i, _ in refused] == list(range(cap, cap + 100))
    code, message = refused[0][1].code, refused[0][1].message
    assert code == macsim.ERR_LIMIT_REACHED
    assert "--max-snapshots" in message and str(cap) in message and "delete" in message, message
    # Without the cap the 110 snapshots would take some 60 MB.
    grown = rss_kib(process) - before
    print(f"macsim grew {grown} KiB for {cap} snapshots kept and 100 refused")
    assert grown <= cap * SNAPSHOT_KIB + MARGIN_KIB, f"grew {grown} KiB"
    assert s.list_snapshots() == sorted(f"client_{i}" for i in range(cap))

    # Full: a name already kept is replaced; a delete frees a place; an unknown name is refused.
    red = s.find_object("environment_01/box_red_small")
    s.set_position(red, (0.4, 0.0, 0.05))
    moved = s.state_hash()
    s.save_snapshot("client_3")
    s.reset(macsim.RESET_EVERYTHING)
    s.restore_snapshot("client_3")
    assert s.state_hash() == moved
    s.delete_snapshot("client_0")
    s.save_snapshot("newcomer")
    with pytest.raises(macsim.SupervisorError) as error:
        s.save_snapshot("one_too_many")
    assert error.value.code == macsim.ERR_LIMIT_REACHED
    with pytest.raises(macsim.SupervisorError) as error:
        s.delete_snapshot("client_0")
    assert error.value.code == macsim.ERR_INVALID_ARGUMENT and "client_0" in error.value.message
    assert len(s.list_snapshots()) == cap


def test_the_byte_budget_refuses_a_snapshot_that_would_pass_it(domain, spawn):
    budget = 2_000_000  # a few snapshots of the demo world after a sweep
    process, s, _ = demo_world(domain, spawn, "--max-snapshot-bytes", str(budget))
    before = rss_kib(process)
    kept = 0
    with pytest.raises(macsim.SupervisorError) as error:
        for i in range(100):
            s.save_snapshot(f"s{i}")
            kept += 1
    assert error.value.code == macsim.ERR_LIMIT_REACHED
    assert "--max-snapshot-bytes" in error.value.message and str(budget) in error.value.message
    size = int(re.search(r"of ([0-9]+) bytes", error.value.message).group(1))
    assert size > 100_000  # the sweep is in it
    assert kept * size <= budget < (kept + 1) * size, (kept, size)
    assert rss_kib(process) - before <= budget // 1024 + MARGIN_KIB
    s.save_snapshot("s0")  # a replacement of the same size fits once the old one is gone
    s.delete_snapshot("s1")
    s.save_snapshot("after_delete")
    assert len(s.list_snapshots()) == kept


def test_bad_snapshot_caps_are_refused_at_the_command_line(domain, spawn):
    for option in (("--max-snapshots", "0"), ("--max-snapshot-bytes", "12abc"),
                   ("--max-pictures", "0")):
        process = spawn([binary("macsim"), "--world", source("worlds/small_room.xml"),
                         "--domain", domain, *option])
        assert process.wait(30) == 2, option
        assert option[0] in process.output(), process.output()
