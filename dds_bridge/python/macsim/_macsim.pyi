"""Type stubs of the `macsim` extension: what each call takes and gives, for editors and
type checkers. Units are SI; vectors are (x, y, z), orientations (x, y, z, w)."""

from typing import Callable, Optional, Sequence

import numpy as np
import numpy.typing as npt

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]

SHAPE_BOX: int
SHAPE_CYLINDER: int
SHAPE_SPHERE: int
KIND_OBJECT: int
KIND_WALL: int
KIND_RAMP: int
KIND_SWITCH_BASE: int
KIND_SWITCH_PLATFORM: int
KIND_DOOR_FRAME: int
KIND_DOOR_LEAF: int
GAP_CLOSED: int
GAP_HALF: int
GAP_OPEN: int
DESTROY_EVERY_OBJECT: int
DESTROY_PORTABLE_OBJECTS: int
DESTROY_FIXED_OBJECTS: int
RESET_POSES: int
RESET_POSES_AND_TIME: int
RESET_EVERYTHING: int
STEP_READ_SIM_TIME: int
STEP_READ_ODOMETRY_X: int
STEP_READ_ODOMETRY_Y: int
STEP_READ_ODOMETRY_YAW: int
STEP_READ_TRUTH_X: int
STEP_READ_TRUTH_Y: int
STEP_READ_TRUTH_Z: int
STEP_READ_CRANE_SLEW: int
STEP_READ_CRANE_LIFT: int
STEP_READ_CRANE_HOIST: int
STEP_READ_CRANE_HOLDING: int
STEP_READ_OBJECT_X: int
STEP_READ_OBJECT_Y: int
STEP_READ_OBJECT_Z: int
STEP_READ_OBJECT_TILT_RATE: int
STEP_TEST_ABOVE: int
STEP_TEST_BELOW: int
STEP_TEST_NEAR: int
STEP_TEST_STALLED: int
STEP_CANCELLED: int
ERR_OK: int
ERR_UNKNOWN_OBJECT: int
ERR_WRONG_GEOMETRY: int
ERR_INVALID_ARGUMENT: int
ERR_NOT_APPLICABLE: int
ERR_PENETRATION: int
ERR_BAD_TEXTURE: int
ERR_BAD_FILE: int
ERR_LIMIT_REACHED: int
ERR_IN_PROGRESS: int
ERR_UNKNOWN_OPERATION: int

class SupervisorError(RuntimeError):
    """A request the simulator refused."""
    code: int
    """ERR_* code."""
    message: str
    names: list[str]
    """The objects a change would penetrate, when that is why."""
    def __init__(self, code: int, message: str, names: Sequence[str] = ...) -> None: ...

class Participant:
    """A Fast DDS participant on one domain: every handle is made on one."""
    def __init__(self, domain: int, profile: Optional[str] = None, name: str = "macsim_python") -> None:
        """Joins DDS domain `domain` (0..232). `profile`: a Fast DDS XML profile file (None:
        FASTRTPS_DEFAULT_PROFILES_FILE, else Fast DDS's defaults)."""
    @property
    def domain(self) -> int: ...

class Component:
    """One shape of an object, in the object's frame."""
    def __init__(self, shape: int, size: Sequence[float], position: Sequence[float] = (0, 0, 0),
                 orientation: Sequence[float] = (0, 0, 0, 1),
                 color: Sequence[float] = (0.5, 0.5, 0.5, 1.0), texture: str = "") -> None:
        """A box (size: full x, y, z), cylinder (radius, -, height; axis z) or sphere (radius)."""
    @property
    def shape(self) -> int: ...
    @property
    def size(self) -> Vec3: ...
    @property
    def position(self) -> Vec3: ...
    @property
    def orientation(self) -> Quat: ...
    @property
    def color(self) -> tuple[float, float, float, float]: ...
    @property
    def texture(self) -> str: ...

class Object:
    """An object of the world: what it is and where it is."""
    @property
    def id(self) -> int: ...
    @property
    def name(self) -> str: ...
    @property
    def kind(self) -> int:
        """KIND_OBJECT, KIND_WALL, KIND_RAMP, ..."""
    @property
    def portable(self) -> bool: ...
    @property
    def components(self) -> list[Component]: ...
    @property
    def position(self) -> Vec3: ...
    @property
    def orientation(self) -> Quat: ...
    @property
    def linear_velocity(self) -> Vec3: ...
    @property
    def angular_velocity(self) -> Vec3: ...
    @property
    def density(self) -> float: ...
    @property
    def mass(self) -> float: ...
    @property
    def material(self) -> str: ...
    @property
    def magnetizable(self) -> bool: ...
    @property
    def frozen(self) -> bool: ...
    @property
    def user_data(self) -> str: ...
    @property
    def user_color(self) -> int: ...
    @property
    def user_shape(self) -> int: ...
    @property
    def ramp(self) -> Vec3:
        """Width, height (m), angle (rad) of a ramp."""

class Odometry:
    """The robot's odometry: pose in odom, velocity in base_link."""
    @property
    def stamp(self) -> float: ...
    @property
    def position(self) -> Vec3: ...
    @property
    def orientation(self) -> Quat: ...
    @property
    def yaw(self) -> float:
        """rad, counter-clockwise from the odom frame's x."""
    @property
    def linear_velocity(self) -> Vec3: ...
    @property
    def angular_velocity(self) -> Vec3: ...

class Imu:
    """The IMU's orientation and rates."""
    @property
    def stamp(self) -> float: ...
    @property
    def orientation(self) -> Quat: ...
    @property
    def yaw(self) -> float: ...
    @property
    def angular_velocity(self) -> Vec3: ...
    @property
    def linear_acceleration(self) -> Vec3: ...

class Scan:
    """One sweep of the laser scanner."""
    @property
    def stamp(self) -> float: ...
    @property
    def frame_id(self) -> str: ...
    @property
    def angle_min(self) -> float: ...
    @property
    def angle_max(self) -> float: ...
    @property
    def angle_increment(self) -> float: ...
    @property
    def range_min(self) -> float: ...
    @property
    def range_max(self) -> float: ...
    @property
    def ranges(self) -> npt.NDArray[np.float32]:
        """m per beam from angle_min (inf: no echo)."""

class CraneState:
    """The crane's joints as measured and its magnet."""
    @property
    def stamp(self) -> float: ...
    @property
    def slew(self) -> float: ...
    @property
    def lift(self) -> float: ...
    @property
    def hoist(self) -> float: ...
    @property
    def magnet_on(self) -> bool: ...
    @property
    def held_object(self) -> str:
        """Name of the object on the magnet, empty if none."""

class StereoFrame:
    """A stereo pair of one instant and its pinhole calibration."""
    stamp: float
    left: npt.NDArray[np.uint8]
    """H x W x 3, BGR."""
    right: npt.NDArray[np.uint8]
    focal: float
    cx: float
    cy: float
    baseline: float

class CameraImage:
    """One camera image and when it was taken."""
    stamp: float
    frame_id: str
    image: npt.NDArray[np.uint8]
    """H x W x 3, BGR, read-only (a view of the received sample)."""

class SimulationStatus:
    """Where the simulation stands after a command."""
    @property
    def sim_time(self) -> float: ...
    @property
    def steps(self) -> int:
        """Steps since the world was loaded."""
    @property
    def state_hash(self) -> int: ...
    @property
    def paused(self) -> bool: ...
    @property
    def real_time_factor(self) -> float: ...
    @property
    def ended_by(self) -> int:
        """step_until: the group of conditions that ended it, -1 (the steps ran out) or
        STEP_CANCELLED."""
    @property
    def samples(self) -> list[float]:
        """step_until: the samples' readings at every check, in order."""
    @property
    def step_trace(self) -> int:
        """step_until(trace_hash=True): every step's state hash mixed in order."""
    @property
    def steps_done(self) -> int:
        """step, step_until, cancel: the steps of the (cancelled) request done."""
    @property
    def steps_asked(self) -> int:
        """step, step_until, cancel: the steps the (cancelled) request asked for."""
    @property
    def message(self) -> str:
        """What the simulator said, e.g. of a cancel."""

class StepCondition:
    """A reading of a step request (STEP_READ_*) and, as a condition, its test (STEP_TEST_*)."""
    def __init__(self, reading: int, test: int = 0, value: float = 0.0, tolerance: float = 0.0,
                 group: int = 0, robot: str = "", object_id: int = 0) -> None: ...
    @property
    def reading(self) -> int: ...
    @property
    def test(self) -> int: ...
    @property
    def value(self) -> float: ...

class Door:
    """A door-switch structure."""
    name: str
    triggered: bool
    virtually_triggered: bool
    gap: int
    opening: float
    switch_travel: float
    object_ids: list[int]
    """The leaf's, frame's, switch platform's and switch base's object ids."""

class Robot:
    """One KURT3D over DDS: the same topics whether macsim or kurt_adapter serves them."""
    def __init__(self, participant: Participant, name: str = "kurt", rotating_laser: bool = True) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def connected(self) -> bool:
        """True once a participant serving this robot's cmd_vel is matched."""
    @property
    def crane_connected(self) -> bool:
        """True once the robot's crane and magnet readers are matched."""
    def cmd_vel(self, linear: float, angular: float) -> bool:
        """m/s forward, rad/s counter-clockwise; repeat it while moving (0.6 s timeout)."""
    def wheel_speeds(self, left: float, right: float) -> bool:
        """Wheel rim speeds, m/s."""
    def stop(self) -> bool: ...
    def wait_delivered(self, timeout: float = 5.0) -> bool:
        """Waits until the robot received every command sent so far."""
    def odometry(self, timeout: float = 5.0) -> Odometry:
        """Waits for an odometry newer than the last one returned; TimeoutError."""
    def latest_odometry(self) -> Optional[Odometry]: ...
    def ranges(self) -> dict[str, float]:
        """The latest IR/sonar readings by frame id, m (-0.01: invalid)."""
    def imu(self, timeout: float = 0.0) -> Optional[Imu]: ...
    def scan(self, after: float = -1.0, timeout: float = 0.0) -> Optional[Scan]: ...
    def points(self, after: float = -1.0, timeout: float = 0.0) -> Optional[npt.NDArray[np.float32]]:
        """The latest 3D cloud later than `after`: N x 3 float32 in base_link, m."""
    def camera(self, side: str = "left", after: float = -1.0, timeout: float = 5.0) -> CameraImage:
        """Camera `side`'s newest image later than `after`, with its stamp; TimeoutError."""
    def image(self, side: str = "left", after: float = -1.0, timeout: float = 5.0) -> npt.NDArray[np.uint8]:
        """Camera `side` ('left'/'right'): read-only H x W x 3 uint8 BGR; TimeoutError."""
    def stereo(self, after: float = -1.0, timeout: float = 5.0) -> StereoFrame: ...
    def crane(self, slew: float, lift: float, hoist: float) -> bool:
        """Joint targets: slew rad, lift rad, hoist m below the tip."""
    def magnet(self, on: bool) -> bool: ...
    def crane_state(self, timeout: float = 0.0) -> Optional[CraneState]: ...
    def rotate_laser(self, speed: float) -> bool:
        """Turns the laser's rotating unit, rad/s (0 stops it)."""

class Supervisor:
    """Every operation on the world's objects and doors; SupervisorError, TimeoutError."""
    timeout: float
    def __init__(self, participant: Participant, timeout: float = 10.0) -> None: ...
    def list_objects(self) -> dict[int, str]: ...
    def find_object(self, name: str) -> int: ...
    def find_by_user_data(self, user_data: str) -> list[int]: ...
    def get_object(self, object_id: int) -> Object: ...
    def create_object(self, name: str, components: Sequence[Component] = (),
                      position: Sequence[float] = (0, 0, 0),
                      orientation: Sequence[float] = (0, 0, 0, 1), *, kind: int = ...,
                      portable: bool = True, density: float = 0.0, mass: float = 0.0,
                      material: str = "", magnetizable: bool = False, frozen: bool = False,
                      user_data: str = "", user_color: int = 0, user_shape: int = 0,
                      ramp: Sequence[float] = (0, 0, 0), allow_penetration: bool = True) -> int: ...
    def import_environment(self, file: str, import_id: str, position: Sequence[float] = (0, 0, 0),
                           orientation: Sequence[float] = (0, 0, 0, 1)) -> list[int]: ...
    def destroy_object(self, object_id: int) -> None: ...
    def destroy_by_user_data(self, user_data: str) -> int: ...
    def destroy_all(self, which: int = ...) -> int: ...
    def set_pose(self, object_id: int, position: Sequence[float],
                 orientation: Sequence[float] = (0, 0, 0, 1), allow_penetration: bool = False) -> None: ...
    def set_position(self, object_id: int, position: Sequence[float], allow_penetration: bool = False) -> None: ...
    def set_orientation(self, object_id: int, orientation: Sequence[float], allow_penetration: bool = False) -> None: ...
    def set_box_size(self, object_id: int, component: int, size: Sequence[float], allow_penetration: bool = False) -> None: ...
    def set_cylinder_size(self, object_id: int, component: int, radius: float, height: float,
                          allow_penetration: bool = False) -> None: ...
    def set_sphere_size(self, object_id: int, component: int, radius: float, allow_penetration: bool = False) -> None: ...
    def set_ramp(self, object_id: int, width: float, height: float, angle: float,
                 allow_penetration: bool = False) -> None: ...
    def set_color(self, object_id: int, rgba: Sequence[float], component: int = -1) -> None: ...
    def set_texture(self, object_id: int, file: str, component: int = -1) -> None: ...
    def set_mass(self, object_id: int, mass: float) -> None: ...
    def set_density(self, object_id: int, density: float) -> None: ...
    def set_linear_velocity(self, object_id: int, velocity: Sequence[float]) -> None: ...
    def set_angular_velocity(self, object_id: int, velocity: Sequence[float]) -> None: ...
    def add_force(self, object_id: int, force: Sequence[float]) -> None: ...
    def add_torque(self, object_id: int, torque: Sequence[float]) -> None: ...
    def set_frozen(self, object_id: int, frozen: bool) -> None: ...
    def set_magnetizable(self, object_id: int, magnetizable: bool) -> None: ...
    def set_user_data(self, object_id: int, user_data: str) -> None: ...
    def set_user_labels(self, object_id: int, color_label: int, shape_label: int) -> None: ...
    def door_count(self) -> int: ...
    def get_door(self, door: int) -> Door: ...
    def set_switch_triggered(self, door: int, triggered: bool) -> None: ...
    def set_door_position(self, door: int, position: Sequence[float]) -> None: ...
    def set_switch_position(self, door: int, position: Sequence[float]) -> None: ...
    def reset(self, scope: int = ...) -> None: ...
    def save_snapshot(self, name: str) -> None: ...
    def restore_snapshot(self, name: str) -> None: ...
    def delete_snapshot(self, name: str) -> None: ...
    def list_snapshots(self) -> list[str]: ...
    def state_hash(self) -> int: ...

class Simulation:
    """Pause, run, real-time factor, lock-step steps, reset, load a world; TimeoutError."""
    timeout: float
    def __init__(self, participant: Participant, timeout: float = 10.0) -> None: ...
    def pause(self) -> SimulationStatus: ...
    def run(self) -> SimulationStatus: ...
    def set_real_time_factor(self, factor: float) -> SimulationStatus:
        """> 0, or 0 for as fast as possible."""
    def step(self, steps: int = 1, timeout: Optional[float] = None) -> SimulationStatus:
        """Lock-step: advances `steps` steps; answered once their data is out. Ctrl-C while it
        waits cancels it on the simulator; a TimeoutError leaves it running (cancel() ends it)."""
    def step_until(self, steps: int, until: list[StepCondition] = ...,
                   samples: list[StepCondition] = ..., check_every: int = 1,
                   publish_at_end: bool = False, cameras: bool = True,
                   hold_commands: bool = False, trace_hash: bool = False,
                   timeout: Optional[float] = None) -> SimulationStatus:
        """Lock-step until a group of conditions holds at a check (or `steps` ran out)."""
    def status(self) -> SimulationStatus: ...
    def cancel(self, sequence_number: int = 0) -> SimulationStatus:
        """Ends this Simulation's step request still running (one a TimeoutError left behind,
        or one another thread waits on); its reply says STEP_CANCELLED. This reply's
        steps_done and steps_asked are the cancelled request's; SupervisorError
        (ERR_NOT_APPLICABLE) if none runs."""
    def reset(self, scope: int = ...) -> SimulationStatus: ...
    def load_world(self, file: str, timeout: float = 60.0) -> SimulationStatus: ...
    def features(self) -> list[str]: ...

class WorldState:
    """The world state topic: the latest state of every object, by id."""
    def __init__(self, participant: Participant) -> None: ...
    def objects(self) -> dict[int, Object]: ...
    def wait(self, check: Callable[[dict[int, Object]], bool], timeout: float = 10.0) -> dict[int, Object]:
        """Waits until check(objects) is true and returns those objects; TimeoutError."""
