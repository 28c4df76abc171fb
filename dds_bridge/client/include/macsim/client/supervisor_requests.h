// Typed supervisor requests (macsim_msgs OP_*), one function per operation: each fills its
// operation's own arguments. Send them with SupervisorClient::call().
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "macsim/msg/macsim_msgs.h"

namespace macsim::client::supervisor {

using Request = macsim_msgs::msg::dds_::SupervisorRequest_;
using Vec3 = std::array<double, 3>;  ///< x, y, z (m, m/s, N, ... as the operation says)
using Quat = std::array<double, 4>;  ///< x, y, z, w (ROS order)
using Rgba = std::array<float, 4>;   ///< each in [0, 1]
inline constexpr Quat kIdentity{0, 0, 0, 1};

Request list_objects();
Request find_object(const std::string& name);
Request find_by_user_data(const std::string& user_data);
Request get_object(uint32_t object_id);
/// `object`: its name, kind (KIND_OBJECT or KIND_RAMP), components, pose, density or mass, ...
Request create_object(const macsim_msgs::msg::dds_::Object_& object, bool allow_penetration = true);
Request import_environment(const std::string& file, const std::string& import_id,
                           const Vec3& position, const Quat& orientation = kIdentity);
Request destroy_object(uint32_t object_id);
Request destroy_by_user_data(const std::string& user_data);
/// `which`: DESTROY_EVERY_OBJECT, DESTROY_PORTABLE_OBJECTS or DESTROY_FIXED_OBJECTS.
Request destroy_all(int32_t which);
Request set_pose(uint32_t object_id, const Vec3& position, const Quat& orientation,
                 bool allow_penetration = false);
Request set_position(uint32_t object_id, const Vec3& position, bool allow_penetration = false);
Request set_orientation(uint32_t object_id, const Quat& orientation,
                        bool allow_penetration = false);
/// Full sizes of a box component, m.
Request set_box_size(uint32_t object_id, int32_t component, const Vec3& size,
                     bool allow_penetration = false);
Request set_cylinder_size(uint32_t object_id, int32_t component, double radius, double height,
                          bool allow_penetration = false);
Request set_sphere_size(uint32_t object_id, int32_t component, double radius,
                        bool allow_penetration = false);
/// Width and height in m, slope angle in rad.
Request set_ramp(uint32_t object_id, double width, double height, double angle,
                 bool allow_penetration = false);
/// `component` -1: every component.
Request set_color(uint32_t object_id, const Rgba& rgba, int32_t component = -1);
/// A BMP of 2^n x 2^n pixels; empty removes the texture. `component` -1: every component.
Request set_texture(uint32_t object_id, const std::string& file, int32_t component = -1);
Request set_mass(uint32_t object_id, double mass);
Request set_density(uint32_t object_id, double density);
Request set_linear_velocity(uint32_t object_id, const Vec3& velocity);
Request set_angular_velocity(uint32_t object_id, const Vec3& velocity);
/// At the centre of mass, world frame, during the next step only.
Request add_force(uint32_t object_id, const Vec3& force);
Request add_torque(uint32_t object_id, const Vec3& torque);
Request set_frozen(uint32_t object_id, bool frozen);
Request set_magnetizable(uint32_t object_id, bool magnetizable);
Request set_user_data(uint32_t object_id, const std::string& user_data);
Request set_user_labels(uint32_t object_id, int32_t color_label, int32_t shape_label);
Request door_count();
Request get_door(int32_t door);
Request set_switch_triggered(int32_t door, bool triggered);
Request set_door_position(int32_t door, const Vec3& position);
Request set_switch_position(int32_t door, const Vec3& position);
/// `scope`: RESET_POSES, RESET_POSES_AND_TIME or RESET_EVERYTHING.
Request reset(int32_t scope);
Request save_snapshot(const std::string& name);
Request restore_snapshot(const std::string& name);
/// Frees the place of the snapshot of that name (macsim keeps --max-snapshots of them).
Request delete_snapshot(const std::string& name);
/// The reply's names: the snapshots kept, in order.
Request list_snapshots();
Request state_hash();

}  // namespace macsim::client::supervisor
