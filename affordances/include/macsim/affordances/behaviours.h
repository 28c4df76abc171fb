// The KURT3D's behaviours, closed-loop on the robot's own topics (odometry, IMU, stereo images,
// laser clouds, crane state; never the supervisor or the world state), shared by every
// controller: look around, go to a thing or to the switch, lift a thing with the crane's magnet,
// put what it holds down on the switch, push a box onto the switch, drive through the door. Each reports the scene as the
// robot perceived it before and after, so the same program drives the simulated and the real
// robot, and a planner can compare what a step did with what it predicted.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "macsim/affordances/kurt_geometry.h"
#include "macsim/affordances/laser_map.h"
#include "macsim/affordances/laser_odometry.h"
#include "macsim/affordances/model.h"
#include "macsim/affordances/robot_loop.h"
#include "macsim/affordances/vision.h"
#include "macsim/client/picture_client.h"

namespace macsim::affordances {

/// Something the cameras found, in the odometry frame: a can, a box, or the switch's platform.
struct SeenThing {
  std::string name;    ///< the colour and a number, "red_1"; "switch" for the switch
  std::string colour;  ///< "red", ..., "yellow" (the switch's platform)
  Kind kind = Kind::Can;
  double above_floor = 0;  ///< m, where the cameras saw its middle (a flush switch's is ~0)
  double x = 0, y = 0;  ///< m, the mean of its sightings
  int seen = 0;         ///< sightings
  bool tried = false;   ///< a lift was tried on it
  bool lost = false;    ///< not found again where it was seen (until it is seen again)
  std::string outcome;  ///< what came of the last behaviour on it
  double liftable = 0;  ///< a lift model's mean probability of `liftable` over the sightings
  int judged = 0;       ///< sightings the model judged
  /// What the cameras see of it from anywhere (thing_features()), the latest sighting's.
  std::map<std::string, double> features;
};

/// The features of a thing the cameras give the same from wherever the robot stands: its hue and
/// its width in metres (perception.h's names; the blob's fill of its box changes with what hides
/// part of it).
const std::vector<std::string>& thing_features();

/// The door's gap as the laser saw it, in the odometry frame.
struct SeenDoor {
  double x = 0, y = 0;    ///< the gap's middle on the wall's line
  double nx = 0, ny = 0;  ///< unit vector across the wall, away from where the robot looked
  double width = 0;       ///< m
};

/// What the robot perceives of the room: itself, the things, the switch, the door.
struct Scene {
  Pose2 robot;
  std::vector<SeenThing> things;
  std::optional<SeenThing> switch_platform;
  std::optional<SeenDoor> door;  ///< a gap of a door's width was seen in the wall
  std::string holding;           ///< the thing on the magnet, or empty
  double held_height = 0;        ///< m, its bottom above the floor, from the crane's state
  std::string at = "start";      ///< the thing or place it last went to
  std::vector<std::string> on_switch;  ///< things it put down on the switch's platform
  bool beyond_door = false;            ///< it drove through the door's gap
};

/// Where the robot is in the scene's atoms: `scene.at`, or "start" when that is a thing it lost
/// sight of (a plan starts from a place of its own then).
std::string robot_place(const Scene& scene);

/// Whether the switch seen is a plate flush with the floor (its yellow seen wide).
bool flush_switch(const Scene& scene);

/// How far from a raised switch platform's middle travel keeps off (m): its base and the tracks'
/// slip beyond the yellow seen, so that what stands on it is not knocked off; 0 when no switch
/// was seen or it is a plate flush with the floor (driven over freely).
double switch_keep_off(const Scene& scene);

/// Why a behaviour did not do what it set out to do.
enum class Setback {
  None,
  NotSeen,       ///< the thing is no longer where it was seen
  NotHeld,       ///< the magnet does not hold it (not magnetizable)
  TooHeavy,      ///< it did not come up
  NoSwitch,      ///< no switch in sight, or not where it was seen
  DoorClosed,    ///< the laser sees the wall without a gap
  NoDoor,        ///< no wall with a door around the robot
  NotThrough,    ///< the robot did not get through the gap
  NotPushed,     ///< the box did not end on the switch
};

/// What a behaviour did: the scene before and after, and whether it did what it set out to do.
struct BehaviourReport {
  std::string behaviour;
  std::string argument;  ///< the thing or place it acted on
  Scene before, after;
  Setback setback = Setback::None;
  std::string reason;  ///< why not, in words
  bool done() const { return setback == Setback::None; }
};

struct BehaviourOptions {
  LoopOptions loop;           ///< robot, lock-step, timeouts
  std::string program = "kurt";  ///< what progress lines begin with ("kurt_demo")
  std::string debug_images;   ///< folder for the camera images with what was seen, or empty
  bool verbose = true;        ///< print progress lines
  bool pictures = false;      ///< ask the simulator for overview pictures (overview_picture())
  /// A lift model to judge each can by while looking (SeenThing::liftable).
  std::optional<AffordanceModel> lift_model;
  /// A traverse model (load_traverse_model) to ask about what stands in the way when no way
  /// round it is free; without one the robot drives on over what it cannot go round.
  std::optional<AffordanceModel> traverse_model;
};

/// Empty, or why `--debug-images DIR` cannot take the camera images (DIR is no folder).
std::string debug_images_problem(const std::string& dir);

/// A controller's behaviours on the robot loop; a program derives from it or holds one.
class Behaviours : public RobotLoop {
 public:
  Behaviours(macsim::dds::Participant& participant, const BehaviourOptions& options);
  ~Behaviours() override;

  /// Finds the robot, parks the crane, starts the laser's rotating unit, maps around it.
  void start();
  /// Stops the drive and the rotating unit.
  void halt();

  /// Progress lines: "PROGRAM: [t=  12.3 s] STAGE: text". Behaviours speak in the stage set last.
  void set_stage(const std::string& stage) { stage_ = stage; }
  void say(const std::string& stage, const std::string& text);
  /// Called as things happen ("lifted", "gap_seen": the door's gap in sight, "through"), e.g. to take a picture.
  std::function<void(const std::string& event)> on_event;

  /// Turns once on the spot, looking (nine stereo pairs); stops early once the switch is seen
  /// if `until_switch`. What a look should have shown near where it was and did not is lost.
  BehaviourReport look_around(bool until_switch = false);
  /// Drives up to 2 m to where the laser sees free floor furthest from every place it looked
  /// around before, and looks around there (what one place hid may show from another; from
  /// where it stands when no floor near is free).
  BehaviourReport look_from_elsewhere();
  /// Walks up to the thing (standing off where the way in is free, looking again from close
  /// by) and drives in until it is at the crane's reach.
  BehaviourReport go_to(const std::string& thing);
  /// Lowers the magnet onto the thing at the crane's reach and lifts it off the floor; lets go
  /// when it does not come up.
  BehaviourReport lift(const std::string& thing);
  /// Goes to the switch (looking around for it first if it was not seen yet).
  BehaviourReport go_to_switch();
  /// Lowers what the magnet holds onto the switch's platform (beside what stands there) and lets go.
  BehaviourReport put_down();
  /// Pushes a box onto the switch: stands behind it on the line from the switch, looks again to
  /// aim at its middle, drives it over the switch with the bumper, backs off and looks whether it
  /// is there.
  BehaviourReport push(const std::string& box);
  /// Goes 1.5 m in front of a door seen from afar (else backs off), watches the wall for its gap
  /// (up to 25 s) and stands in front of it.
  BehaviourReport go_to_door();
  /// Drives through the door's gap (going to the door first unless it stands there).
  BehaviourReport drive_through();
  /// Takes a laser cloud where the robot stands and looks for the door's gap in the wall: the
  /// scene's door is the gap, or none when the wall is seen whole; unchanged when no wall is in
  /// sight. True when a wall was seen.
  bool perceive_door();
  /// Whether the door is seen open, and again a while later (not a passing press of the switch).
  bool door_stays_open();

  /// An overview picture from the simulator (macsim --pictures DIR) named `name`, seen from the
  /// Chase camera: its file, said under the stage `name`. Nothing when pictures were not asked for,
  /// or (said once, then no more asked) nothing serves them: a real robot has no overview camera.
  std::optional<std::string> overview_picture(const std::string& name);

  const Scene& scene() const { return scene_; }
  /// A thing of the scene by name (nullptr if there is none).
  SeenThing* thing(const std::string& name);
  int lift_attempts() const { return lift_attempts_; }

 protected:
  /// Records sightings into the scene (names new things).
  void record(const std::vector<std::pair<Sighting, Pose2>>& sightings);

 private:
  void emit(const std::string& event);
  void park_crane();
  std::string lower_onto(double lift, double height, bool until_held);
  /// Brings the robot to rest and hands each of the next `frames` camera frames to `use`.
  void for_frames(int frames, const std::function<void(const macsim::client::StereoFrame&)>& use);
  std::vector<std::pair<Sighting, Pose2>> look(int frames = 1);
  /// Where a few frames put a flush plate's middle judged from its outline (odometry frame).
  std::optional<Point> look_at_flush_plate();
  /// One 3D laser cloud, the robot's pose corrected by laser odometry on the way (what stands
  /// still laid onto what stood still in the clouds before: the tracks' slip taken out).
  macsim::client::Cloud located_cloud();
  void map_here();
  /// Marks a raised switch platform seen as an obstacle: travel keeps off what stands on it.
  void keep_off_the_switch();
  /// Whether `at` lies on the raised switch platform kept off.
  bool on_raised_switch(Point at) const;
  Point approach_point(Point target, double standoff, double reach) const;
  /// Drives to `goal`: straight when the way is free, else by a waypoint beside it; when neither
  /// is free, what stands in the way is judged by the traverse model (if any) and what it calls
  /// traversable is driven over; then by the shortest way round what the laser sees, or on.
  void travel_to(Point goal, double tolerance);
  /// The shortest way to `goal` over the floor the obstacle map leaves free (A* on 5 cm cells,
  /// every obstacle grown by half the robot's corridor), as waypoints; empty when there is none.
  std::vector<Point> way_round(Point goal) const;
  /// A waypoint beside the straight way to `goal` from which both legs are free, if any.
  std::optional<Point> detour(Point goal) const;
  /// Judges the first thing the obstacle map has on the straight way to `goal` by the traverse
  /// model, standing before it as a traverse trial stood; false when there was nothing new to
  /// judge.
  bool judge_in_way(Point goal);
  /// Where the cameras see the target again (within `radius` of where it was), looking about
  /// and from further back when they do not at first; `last`, if given, gets the last sighting.
  std::optional<Point> find_again(const SeenThing& target, Kind kind, double radius = 0.45,
                                  Sighting* last = nullptr);
  bool close_in(SeenThing& target, Kind kind);
  /// Closes in on the switch by the thing put in its platform's middle, seen where it was put
  /// (from close by, that thing hides the middle of the yellow); false with nothing on it.
  bool close_in_by_what_is_on_it();
  /// Marks lost each thing this look should have shown (well inside the view, 1-3 m away, not
  /// held, not on the switch) but did not, near where it was: after the tracks slipped, what
  /// the robot remembers lies where nothing is.
  void forget_unseen(const std::vector<std::pair<Sighting, Pose2>>& seen);
  BehaviourReport report(const std::string& behaviour, const std::string& argument) const;
  BehaviourReport& finish(BehaviourReport& r, Setback setback = Setback::None,
                          const std::string& reason = {});

  BehaviourOptions options_;
  KurtGeometry geometry_;
  std::string stage_;
  Scene scene_;
  int lift_attempts_ = 0;
  ObstacleMap obstacles_;
  int debug_count_ = 0;
  std::vector<Point> looked_from_;  ///< odometry frame: where it looked around
  std::set<std::pair<int, int>> judged_;  ///< traverse cells (cell_of) judged already
  StaticMap static_map_;  ///< what stood still in the clouds taken (laser odometry)
  Pose2 cloud_pose_;      ///< where the last cloud was taken
  Point middle_from_first_;  ///< the platform's middle from the first thing put on it
  bool pushing_ = false;  ///< a push under way (its tracks slip against the box by design)
  double view_half_angle_ = 0;  ///< rad, half the cameras' horizontal view (from the last frame)
  std::unique_ptr<macsim::client::PictureClient> pictures_;  ///< while pictures are asked for and served
};

}  // namespace macsim::affordances
