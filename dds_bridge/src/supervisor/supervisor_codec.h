// The supervisor's wire types (macsim_msgs) to and from sim_core's: poses, objects, doors,
// events, error codes. Every sim_core enum that travels is tied to its wire value here.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "macsim/msg/macsim_msgs.h"
#include "macsim/sim_core/command.h"
#include "macsim/sim_core/world.h"

namespace macsim::codec {

namespace mm = macsim_msgs::msg::dds_;
namespace gm = geometry_msgs::msg::dds_;

gm::Pose_ pose_message(const Pose& pose);
/// The pose a message carries; its quaternion as given (not normalized).
Pose pose_of(const gm::Pose_& pose);
Eigen::Vector3d vector_of(const gm::Vector3_& v);
Eigen::Vector3d vector_of(const gm::Point_& p);
/// (w, x, y, z) from the message's x, y, z, w.
Eigen::Quaterniond quaternion_of(const gm::Quaternion_& q);
/// An object's description and state as the world holds them (an empty message if unknown).
mm::Object_ object_message(const World& world, ObjectId id);
/// The description an Object_ asks for; nullopt and `error` set when a code is not one of ours.
std::optional<ObjectSpec> spec_of(const mm::Object_& object, std::string& error);
mm::Door_ door_message(const World& world, int door);
/// The event's wire name ("switch_triggered", "door_opened", "attached", ...).
const char* event_name(WorldEvent::Type type);
/// The wire code of a sim_core error.
int32_t error_code(ErrorCode code);
/// The robot commands a request names as sent before it (commands_sent), as the runner keeps
/// them.
std::vector<Sender> senders(const std::vector<mm::SampleIdentity_>& commands_sent);

}  // namespace macsim::codec
