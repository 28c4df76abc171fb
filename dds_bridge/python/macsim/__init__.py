"""MACSim-DDS from Python: drive a KURT3D (in the simulator or the real robot's adapter),
supervise and step the simulator, all over DDS through the project's C++ client library.

    import macsim
    p = macsim.Participant(domain=7)
    kurt = macsim.Robot(p, "kurt")
    kurt.cmd_vel(0.3, 0.0)
    print(kurt.odometry(timeout=5).position)
    left = kurt.image("left")            # H x W x 3 uint8 numpy array (BGR)
    lift = macsim.affordances.load("models/lift.yml")   # a learned model (affordance_learn)

Blocking calls release the GIL, hear Ctrl-C, and raise TimeoutError when nobody answers.
"""

from ._macsim import (
    AffordanceModel,
    AffordanceModelError,
    CameraImage,
    Component,
    CraneState,
    Door,
    Imu,
    Object,
    Odometry,
    Participant,
    PddlError,
    Robot,
    Scan,
    SimulationStatus,
    Simulation,
    StepCondition,
    StereoFrame,
    Supervisor,
    SupervisorError,
    WorldState,
    affordance_feature_group,
    affordance_features,
    kurt3d_description,
    load_sensor_inputs,
    objects_in_view,
    plan_files,
)
from ._macsim import (
    DESTROY_EVERY_OBJECT,
    DESTROY_FIXED_OBJECTS,
    DESTROY_PORTABLE_OBJECTS,
    ERR_BAD_FILE,
    ERR_BAD_TEXTURE,
    ERR_IN_PROGRESS,
    ERR_INVALID_ARGUMENT,
    ERR_LIMIT_REACHED,
    ERR_NOT_APPLICABLE,
    ERR_OK,
    ERR_PENETRATION,
    ERR_UNKNOWN_OBJECT,
    ERR_UNKNOWN_OPERATION,
    ERR_WRONG_GEOMETRY,
    GAP_CLOSED,
    GAP_HALF,
    GAP_OPEN,
    KIND_DOOR_FRAME,
    KIND_DOOR_LEAF,
    KIND_OBJECT,
    KIND_RAMP,
    KIND_SWITCH_BASE,
    KIND_SWITCH_PLATFORM,
    KIND_WALL,
    RESET_EVERYTHING,
    RESET_POSES,
    RESET_POSES_AND_TIME,
    SHAPE_BOX,
    SHAPE_CYLINDER,
    SHAPE_SPHERE,
    STEP_CANCELLED,
    STEP_READ_CRANE_HOIST,
    STEP_READ_CRANE_HOLDING,
    STEP_READ_CRANE_LIFT,
    STEP_READ_CRANE_SLEW,
    STEP_READ_OBJECT_TILT_RATE,
    STEP_READ_OBJECT_X,
    STEP_READ_OBJECT_Y,
    STEP_READ_OBJECT_Z,
    STEP_READ_ODOMETRY_X,
    STEP_READ_ODOMETRY_Y,
    STEP_READ_ODOMETRY_YAW,
    STEP_READ_SIM_TIME,
    STEP_READ_TRUTH_X,
    STEP_READ_TRUTH_Y,
    STEP_READ_TRUTH_Z,
    STEP_TEST_ABOVE,
    STEP_TEST_BELOW,
    STEP_TEST_NEAR,
    STEP_TEST_STALLED,
)

__all__ = [name for name in dir() if not name.startswith("_")]

from . import affordances  # noqa: E402  (macsim.affordances.load; a module, not in __all__)
