// Writes the fuzzers' seed inputs into a directory (one folder per target): every world of the
// repository bundled with its imports and textures, one supervisor request per operation and
// each simulation command on the demonstrator world, and the KURT's frames and commands.
// usage: make_fuzz_seeds OUT_DIR
#include <fastdds/rtps/common/SerializedPayload.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <set>
#include <sstream>

#include "fuzz_input.h"
#include "macsim/client/supervisor_requests.h"
#include "macsim/kurt/kurt_can.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/sim_core/session.h"
#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "snapshot_scene.h"
#include "supervisor/supervisor_codec.h"

namespace fs = std::filesystem;
namespace mm = macsim_msgs::msg::dds_;
namespace rq = macsim::client::supervisor;
using macsim::fuzz::record;

namespace {

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void write(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// Adds `file` (named `name` relative to the root's folder) and what it imports or textures.
void bundle(const fs::path& root_dir, const fs::path& file, std::set<std::string>& names,
            std::string& out) {
  static const std::regex reference("<(NAME|TEXTURE)>\\s*([^<]+?\\.(xml|bmp))\\s*</");
  const std::string text = read(file);
  for (std::sregex_iterator m(text.begin(), text.end(), reference), end; m != end; ++m) {
    const fs::path target = (file.parent_path() / (*m)[2].str()).lexically_normal();
    const std::string name = target.lexically_relative(root_dir).string();
    if (!fs::is_regular_file(target) || !names.insert(name).second) continue;
    out += std::string(macsim::fuzz::kFileMark) + name + "\n" + read(target);
    if (target.extension() == ".xml") bundle(root_dir, target, names, out);
  }
}

template <class PubSubType, class Sample>
std::string to_wire(Sample sample) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&sample)());
  type.serialize(&sample, &payload);
  return std::string(reinterpret_cast<const char*>(payload.data), payload.length);
}

std::string supervisor(mm::SupervisorRequest_ request) {
  return record(0, to_wire<mm::SupervisorRequest_PubSubType>(std::move(request)));
}

std::string simulation(int32_t command, double rtf = 1.0, uint64_t steps = 0) {
  mm::SimulationRequest_ request;
  request.command(command);
  request.real_time_factor(rtf);
  request.steps(steps);
  return record(1, to_wire<mm::SimulationRequest_PubSubType>(request));
}

std::string frame(const macsim::kurt::CanFrame& frame) {
  const auto bytes = macsim::kurt::to_datagram(frame);
  return record(0, std::string(bytes.begin(), bytes.end()));
}

std::string numbers(uint8_t kind, std::initializer_list<double> values) {
  std::string bytes;
  for (double v : values) bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  return record(kind, bytes);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]).rfind("-", 0) == 0) {
    std::cerr << "usage: make_fuzz_seeds OUT_DIR\n";
    return argc == 2 && std::string(argv[1]) == "--help" ? 0 : 2;
  }
  const fs::path out = argv[1];
  const fs::path worlds = fs::path(MACSIM_SOURCE_DIR) / "worlds";
  for (const char* target : {"world_loader", "requests", "kurt_can", "snapshot", "session"}) {
    fs::create_directories(out / target);
  }

  for (const auto& entry : fs::directory_iterator(worlds)) {
    if (entry.path().extension() != ".xml") continue;
    std::string seed = read(entry.path());
    std::set<std::string> names;
    bundle(worlds, entry.path(), names, seed);
    write(out / "world_loader" / entry.path().stem(), seed);
  }

  const macsim::World world(macsim::load_world_file((worlds / "DemoWorld_v1.xml").string()));
  const uint32_t box = *world.objects().find_object("environment_01/box_red_small");
  const uint32_t ball = *world.objects().find_object("environment_01/ball_green");
  const uint32_t ramp = *world.objects().find_object("environment_02/ramp_00");
  mm::Object_ copy = macsim::codec::object_message(world, ball);
  copy.name("seed/ball");
  copy.pose().position().y(-1.0);
  const std::string env = (worlds / "DemoEnvironment_v1/objects/blocks.xml").string();
  const std::string texture = (worlds / "DemoEnvironment_v1/textures/wood.bmp").string();
  const std::vector<std::pair<std::string, std::string>> requests{
      {"list", supervisor(rq::list_objects())},
      {"find", supervisor(rq::find_object("environment_01/ball_green"))},
      {"find_user_data", supervisor(rq::find_by_user_data("x"))},
      {"get", supervisor(rq::get_object(box))},
      {"create", supervisor(rq::create_object(copy))},
      {"import", supervisor(rq::import_environment(env, "more", {0, -1.5, 0}))},
      {"destroy", supervisor(rq::destroy_object(box))},
      {"destroy_user_data", supervisor(rq::destroy_by_user_data("x"))},
      {"destroy_all", supervisor(rq::destroy_all(mm::DESTROY_PORTABLE_OBJECTS))},
      {"pose", supervisor(rq::set_pose(box, {0, -1, 0.3}, {0, 0, 0, 1}))},
      {"position", supervisor(rq::set_position(box, {0, -1, 0.3}))},
      {"orientation", supervisor(rq::set_orientation(box, {0, 0, 0.7071, 0.7071}))},
      {"box", supervisor(rq::set_box_size(box, 0, {0.2, 0.1, 0.1}))},
      {"cylinder", supervisor(rq::set_cylinder_size(box, 0, 0.05, 0.1))},
      {"sphere", supervisor(rq::set_sphere_size(ball, 0, 0.08))},
      {"ramp", supervisor(rq::set_ramp(ramp, 0.5, 0.1, 0.3))},
      {"color", supervisor(rq::set_color(box, {0.1f, 0.2f, 0.3f, 1.0f}))},
      {"texture", supervisor(rq::set_texture(box, texture))},
      {"mass", supervisor(rq::set_mass(box, 2.0))},
      {"density", supervisor(rq::set_density(box, 500.0))},
      {"velocity", supervisor(rq::set_linear_velocity(ball, {1, 0, 0}))},
      {"spin", supervisor(rq::set_angular_velocity(ball, {0, 0, 3}))},
      {"force", supervisor(rq::add_force(ball, {0, 0, 20}))},
      {"torque", supervisor(rq::add_torque(ball, {0, 0, 1}))},
      {"frozen", supervisor(rq::set_frozen(ball, true))},
      {"magnetizable", supervisor(rq::set_magnetizable(box, true))},
      {"user_data", supervisor(rq::set_user_data(box, "x"))},
      {"labels", supervisor(rq::set_user_labels(box, 1, 2))},
      {"door_count", supervisor(rq::door_count())},
      {"door", supervisor(rq::get_door(0))},
      {"switch", supervisor(rq::set_switch_triggered(0, true))},
      {"door_position", supervisor(rq::set_door_position(0, {0, 0, 0.1}))},
      {"switch_position", supervisor(rq::set_switch_position(0, {0, 0, 0.01}))},
      {"reset", supervisor(rq::reset(mm::RESET_EVERYTHING))},
      {"snapshots", supervisor(rq::save_snapshot("a")) +
                        supervisor(rq::add_force(ball, {0, 0, 9})) +
                        supervisor(rq::restore_snapshot("a"))},
      {"hash", supervisor(rq::state_hash())},
      {"simulation", simulation(mm::SIM_RUN) + simulation(mm::SIM_SET_RTF, 2.0) +
                         simulation(mm::SIM_PAUSE) + simulation(mm::SIM_STEP, 0, 5) +
                         simulation(mm::SIM_STATUS) + simulation(mm::SIM_FEATURES)},
  };
  for (const auto& [name, bytes] : requests) write(out / "requests" / name, bytes);

  using namespace macsim::kurt;
  write(out / "kurt_can" / "drive", numbers(1, {0.3, 0.2}) + numbers(4, {0.01}) +
                                        frame(encode_encoder({120, 130})) + numbers(4, {0.01}) +
                                        frame(encode_encoder({-40, 60})) + numbers(2, {0.1, -0.1}) +
                                        numbers(4, {0.7}));
  write(out / "kurt_can" / "sensors",
        frame(encode_adc({0, {100, 200, 300, 400}})) + frame(encode_adc({4, {500, 600, 0, 1}})) +
            frame(encode_adc({8, {700, 800, 900, 1000}})) + frame(encode_gyro(4992511 * 90, 50)) +
            frame(encode_tilt(32768, 33000)) + frame(encode_rotunit_angle(2560)));
  write(out / "kurt_can" / "host", frame(encode_speed_cm({0.2, 0.3})) + frame(encode_hard_stop()) +
                                       frame(encode_actuator(true)) +
                                       frame(encode_rotunit_speed(1.0)) + numbers(3, {2.0}));
  // Snapshots of the scene fuzz_snapshot restores (the same world: the same fingerprint).
  const auto scene = macsim::fuzz::snapshot_scene();
  int moment = 0;
  for (const auto& snapshot : macsim::fuzz::snapshot_scene_moments(*scene)) {
    write(out / "snapshot" / ("moment_" + std::to_string(moment++)),
          std::string(snapshot.bytes.begin(), snapshot.bytes.end()));
  }
  // Sessions: every kind of record, written by the session writer's own format.
  {
    macsim::Session session;
    session.header.world_file = "worlds/small_room.xml";
    session.header.seed = 3;
    session.files.push_back({"worlds/small_room.xml", "<WORLD><NAME>a</NAME></WORLD>\n", 0});
    session.hashes.push_back({0, 0x0123456789abcdefULL});
    macsim::RecordedCommand twist{0, macsim::robot_command("kurt", macsim::robot::Twist{0.2, 0.3})};
    session.commands.push_back(twist);
    macsim::RecordedCommand keep;
    keep.command =
        macsim::request_command<macsim::KeepRobotCommands>(macsim::CommandSource::Simulation);
    for (uint64_t step = 5; step < 9; ++step) {
      keep.step = step;
      session.commands.push_back(keep);
    }
    macsim::RecordedCommand request;
    request.step = 12;
    auto recorded = std::make_shared<macsim::WireRequest>();
    recorded->operation = "set_density";
    recorded->bytes = {0x00, 0x01, 0x02, 0xff};
    request.command.source = macsim::CommandSource::Supervisor;
    request.command.request = recorded;
    session.commands.push_back(request);
    session.files.push_back({"../other/moved world.xml", "bytes\x00\x01", 6});
    session.hashes.push_back({50, 0xfedcba9876543210ULL});
    session.steps = 60;
    macsim::write_session((out / "session" / "recorded").string(), session);
  }
  std::cout << "make_fuzz_seeds: wrote seeds to " << out.string() << "\n";
  return 0;
}
