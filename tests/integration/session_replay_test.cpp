// Sessions end to end: macsim --record-session while kurt_demo plays the final demonstrator (a
// seeded layout, from a copy of its world files deleted once recorded) in real time (commands
// arriving as the controller sends them, not lock-step), then macsim --replay from the file
// alone, in an empty folder, meets every hash; one command changed is reported at the first hash
// after it; a damaged or other-version file, or an altered embedded world, is refused with its
// line. A session with supervisor requests, a ROS 2 service and a world load replays too.
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "macsim/client/supervisor_client.h"
#include "macsim/dds/convert.h"
#include "macsim/msg/simulation_interfacesPubSubTypes.h"
#include "macsim/sim_core/session.h"
#include "support/child_process.h"
#include "support/ros2_service_calls.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;
namespace supervisor = client::supervisor;

/// The hash-equal line of a replay's output: "all N hashes equal".
std::optional<int> hashes_equal(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex("all ([0-9]+) hashes equal"))) return std::nullopt;
  return std::stoi(m[1]);
}

/// The step a replay says differs first.
std::optional<uint64_t> differs_at(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex("differs at step ([0-9]+)"))) return std::nullopt;
  return std::stoull(m[1]);
}

struct Replay {
  int exit_code = -1;
  std::string output;
};

/// macsim --replay `file` (and `more`), started in `folder` (empty: this process's).
Replay replay(const std::string& file, const std::string& folder = "",
              std::vector<std::string> more = {}) {
  std::vector<std::string> args{bin("macsim"), "--replay", file};
  args.insert(args.end(), more.begin(), more.end());
  macsim::process::Options options;
  options.working_directory = folder;
  ChildProcess p(args, options);
  Replay r;
  r.exit_code = p.wait_for_exit(180s).value_or(-1);
  r.output = p.output();
  return r;
}

/// One recorded run of the demonstrator for every test of the suite (100 s of robot time, about
/// 35 s of wall time at real-time factor 3).
class DemonstratorSession : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    namespace fs = std::filesystem;
    dir_ = new TempDir("macsim_session_");
    path_ = dir_->path() + "/demonstrator.session";
    // The world's files are a copy, deleted once recorded: the replay has only the session.
    const std::string copy = dir_->path() + "/world";
    fs::create_directories(copy);
    fs::copy(source("worlds/DemoWorld_v1.xml"), copy);
    fs::copy(source("worlds/DemoEnvironment_v1"), copy + "/DemoEnvironment_v1",
             fs::copy_options::recursive);
    world_ = copy + "/DemoWorld_v1.xml";
    const std::string domain = std::to_string(unique_test_domain());
    // Seed 5: one of the quickest layouts (97 s of robot time in lock-step, one lift). In real
    // time, three times as fast as the robot would move: the commands still come when they come
    // (not on request), and the run takes a third of the wall time.
    ChildProcess macsim({bin("macsim"), "--world", world_, "--seed", "5", "--domain", domain,
                         "--rtf", "3", "--record-session", path_});
    ASSERT_TRUE(macsim.wait_for_output("stepping at real-time factor 3", 30s)) << macsim.output();
    ChildProcess demo({bin("kurt_demo"), "--domain", domain});
    demo_exit_ = demo.wait_for_exit(240s).value_or(-1);
    demo_output_ = demo.output();
    macsim.signal(SIGINT);
    macsim_exit_ = macsim.wait_for_exit(20s).value_or(-1);
    macsim_output_ = macsim.output();
    world_bytes_ = read_text(world_);
    fs::remove_all(copy);
  }
  static std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream whole;
    whole << in.rdbuf();
    return whole.str();
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  static TempDir* dir_;
  static std::string path_, world_, world_bytes_, demo_output_, macsim_output_;
  static int demo_exit_, macsim_exit_;
};
TempDir* DemonstratorSession::dir_ = nullptr;
std::string DemonstratorSession::path_, DemonstratorSession::world_,
    DemonstratorSession::world_bytes_, DemonstratorSession::demo_output_,
    DemonstratorSession::macsim_output_;
int DemonstratorSession::demo_exit_ = -1, DemonstratorSession::macsim_exit_ = -1;

TEST_F(DemonstratorSession, ReplaysWithEveryHashEqual) {
  ASSERT_EQ(demo_exit_, 0) << demo_output_;
  EXPECT_NE(demo_output_.find("SUCCESS"), std::string::npos) << demo_output_;
  ASSERT_EQ(macsim_exit_, 0) << macsim_output_;
  EXPECT_NE(macsim_output_.find("session recorded to " + path_), std::string::npos);
  const Session session = read_session(path_);
  // About 100 s at 1 ms a step, a hash every 100 steps, the controller's commands all along.
  EXPECT_GT(session.steps, 80000u);
  EXPECT_EQ(session.hashes.size(), session.steps / 100 + 1);
  EXPECT_GT(session.commands.size(), 2000u);
  std::map<std::string, int> operations;
  for (const auto& c : session.commands) ++operations[std::string(operation_name(c.command))];
  EXPECT_GT(operations["twist"], 100);
  EXPECT_GT(operations["crane"], 100);
  EXPECT_GT(operations["magnet"], 10);
  // One file: the world and every file it imports, read before the first command, the seed.
  EXPECT_EQ(session.header.world_file, world_);
  EXPECT_EQ(session.header.seed, 5);
  ASSERT_FALSE(session.files.empty());
  EXPECT_EQ(session.files.front().path, world_);
  EXPECT_EQ(session.files.front().bytes, world_bytes_);
  EXPECT_EQ(session.files.front().commands_before, 0u);
  EXPECT_GE(session.files.size(), 8u);  // the world, materials, room, doors, objects, robot
  EXPECT_FALSE(std::filesystem::exists(world_));
  // Moved to an empty folder and replayed there.
  const TempDir empty("macsim_replay_");
  std::filesystem::copy(path_, empty.path() + "/demonstrator.session");
  const Replay r = replay("demonstrator.session", empty.path());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(hashes_equal(r.output), static_cast<int>(session.hashes.size())) << r.output;
}

TEST_F(DemonstratorSession, ExtractGivesTheWorldFilesBack) {
  ASSERT_EQ(macsim_exit_, 0) << macsim_output_;
  const TempDir out("macsim_extract_");
  const Replay r = replay(path_, "", {"--extract", out.path()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_text(out.path() + "/" + std::filesystem::path(world_).relative_path().string()),
            world_bytes_)
      << r.output;
  EXPECT_NE(r.output.find("DemoEnvironment_v1/robot.xml"), std::string::npos) << r.output;
}

TEST_F(DemonstratorSession, AnAlteredEmbeddedWorldIsRefusedAtLoad) {
  ASSERT_EQ(macsim_exit_, 0) << macsim_output_;
  std::string text = read_text(path_);
  // One byte of the world's XML changed: a digit of its hex.
  const std::size_t line = text.find("\nf ") + 1;
  const std::size_t bytes = text.find(' ', text.find(' ', line + 2) + 1) + 1;
  text[bytes + 40] = text[bytes + 40] == '3' ? '4' : '3';
  const std::string altered = dir_->path() + "/altered_world.session";
  std::ofstream(altered) << text;
  const Replay r = replay(altered);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("does not match its checksum"), std::string::npos) << r.output;
  const int line_number = int(std::count(text.begin(), text.begin() + long(line), '\n')) + 1;
  EXPECT_NE(r.output.find(altered + ":" + std::to_string(line_number) + ":"), std::string::npos)
      << r.output;
}

TEST_F(DemonstratorSession, OneChangedCommandIsReportedAtTheFirstHashAfterIt) {
  ASSERT_EQ(macsim_exit_, 0) << macsim_output_;
  Session session = read_session(path_);
  // A drive command in the middle of the run that no later command replaces in the same step.
  std::size_t pick = session.commands.size() / 2;
  const auto superseded = [&](std::size_t i) {
    for (std::size_t j = i + 1; j < session.commands.size(); ++j) {
      if (session.commands[j].step != session.commands[i].step) return false;
      if (operation_name(session.commands[j].command) == "twist") return true;
    }
    return false;
  };
  while (pick < session.commands.size() &&
         (operation_name(session.commands[pick].command) != "twist" || superseded(pick)))
    ++pick;
  ASSERT_LT(pick, session.commands.size());
  RecordedCommand& changed = session.commands[pick];
  const macsim::robot::Twist twist = *changed.command.robot->as<macsim::robot::Twist>();
  changed.command.robot = macsim::robot::Twist{twist.linear + 0.05, twist.angular};  // 5 cm/s
  const std::string path = dir_->path() + "/changed.session";
  write_session(path, session);
  const Replay r = replay(path);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const uint64_t hash_every = session.header.hash_every;
  const uint64_t first_hash_after = (changed.step / hash_every + 1) * hash_every;
  EXPECT_EQ(differs_at(r.output), first_hash_after)
      << "changed the twist at step " << changed.step << "\n"
      << r.output;
  EXPECT_NE(r.output.find("the last equal hash was at step " +
                          std::to_string(first_hash_after - hash_every)),
            std::string::npos)
      << r.output;
}

TEST_F(DemonstratorSession, ADamagedOrOtherVersionFileIsRefused) {
  const std::string text = read_text(path_);
  const std::string other = dir_->path() + "/other_version.session";
  std::ofstream(other) << "macsim-session 99" << text.substr(text.find('\n'));
  Replay r = replay(other);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(
      r.output.find(other + ":1: session format version 99; this macsim reads versions 1 to 6"),
      std::string::npos)
      << r.output;
  const std::string cut = dir_->path() + "/cut.session";
  std::ofstream(cut) << text.substr(0, text.size() / 3);
  r = replay(cut);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("cut short"), std::string::npos) << r.output;
  const std::string garbled = dir_->path() + "/garbled.session";
  std::string g = text;
  const std::size_t command = g.find("\nc ") + 1;
  g.replace(command, 2, "x ");
  std::ofstream(garbled) << g;
  r = replay(garbled);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not a session record"), std::string::npos) << r.output;
  EXPECT_EQ(replay(dir_->path() + "/missing.session").exit_code, 2);
}

// A session names the wire types it was written with; one of other types (an IDL type changed
// since) is refused at once by replay, resume and compare, naming both, before any byte of it is
// decoded.
TEST_F(DemonstratorSession, ASessionOfOtherWireTypesIsRefusedNamingBoth) {
  const std::string text = read_text(path_);
  const std::size_t line = text.find("\nwire-types ") + 1;
  ASSERT_NE(line, 0u) << text.substr(0, 300);
  const std::size_t end = text.find('\n', line);
  const std::string ours = text.substr(line + 11, end - line - 11);
  ASSERT_EQ(ours.size(), 16u) << ours;
  const std::string theirs = ours == "0123456789abcdef" ? "fedcba9876543210" : "0123456789abcdef";
  std::string changed = text;
  changed.replace(line + 11, ours.size(), theirs);
  const std::string other = dir_->path() + "/other_types.session";
  std::ofstream(other) << changed;
  const std::string said =
      other + ": recorded with wire types " + theirs + ", this macsim's are " + ours;
  Replay r = replay(other);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(said), std::string::npos) << r.output;
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--compare", path_, other},
        std::vector<std::string>{"--resume", other, "--domain",
                                 std::to_string(unique_test_domain())}}) {
    std::vector<std::string> command{bin("macsim")};
    command.insert(command.end(), args.begin(), args.end());
    ChildProcess macsim(command);
    EXPECT_EQ(macsim.wait_for_exit(30s), 2) << args.front() << ": " << macsim.output();
    EXPECT_NE(macsim.output().find(said), std::string::npos)
        << args.front() << ": " << macsim.output();
  }
}

TEST(SessionReplay, SupervisorRequestsAServiceAndALoadReplay) {
  TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/supervised.session";
  const int domain = unique_test_domain();
  ChildProcess macsim({bin("macsim"), "--world", source("worlds/DemoWorld_v1.xml"), "--domain",
                       std::to_string(domain), "--cameras", "off", "--record-session", path,
                       "--session-hash-every", "10"});
  ASSERT_TRUE(macsim.wait_for_output("stepping", 30s)) << macsim.output();
  {
    dds::Participant participant({domain, "", "session_test"});
    client::SupervisorClient sv(participant);
    client::SimulationClient sim(participant);
    ASSERT_TRUE(sv.wait_for_server(20s));
    const auto can = sv.call(supervisor::find_object("environment_01/ball_green"));
    ASSERT_TRUE(can && can->code() == mm::ERR_OK);
    for (int i = 0; i < 5; ++i) {
      auto r = sv.call(supervisor::add_force(can->object_id(), {0.0, 3.0, 8.0}));
      ASSERT_TRUE(r && r->code() == mm::ERR_OK);
      std::this_thread::sleep_for(50ms);
    }
    auto r = sv.call(supervisor::set_density(can->object_id(), 450.0));
    ASSERT_TRUE(r && r->code() == mm::ERR_OK);
    // A ROS 2 service (simulation_interfaces) spawns a crate where the ball was.
    namespace ss = simulation_interfaces::srv::dds_;
    Ros2ServiceCalls services(participant);
    ss::SpawnEntity_Request_ spawn;
    spawn.name("crate");
    spawn.resource_string(
        "<ENVIRONMENT><OBJECT><ID>box</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE>"
        "<DIMS>0.2,0.2,0.2</DIMS><POS>0,0,0.1</POS></OBJECT></ENVIRONMENT>");
    spawn.initial_pose().pose().position().x(-1.0);
    spawn.initial_pose().pose().position().z(0.3);
    spawn.initial_pose().pose().orientation().w(1);
    const auto spawned =
        services.call<ss::SpawnEntity_Request_PubSubType, ss::SpawnEntity_Response_PubSubType>(
            "spawn_entity", spawn);
    ASSERT_EQ(spawned.result().result(), 1) << spawned.result().error_message();  // RESULT_OK
    r = sv.call(supervisor::save_snapshot("before"));
    ASSERT_TRUE(r && r->code() == mm::ERR_OK);
    std::this_thread::sleep_for(300ms);
    r = sv.call(supervisor::restore_snapshot("before"));
    ASSERT_TRUE(r && r->code() == mm::ERR_OK);
    auto load = client::SimulationClient::request(mm::SIM_LOAD_WORLD);
    load.world_file(source("worlds/small_room.xml"));
    auto loaded = sim.call(load);
    ASSERT_TRUE(loaded && loaded->code() == mm::ERR_OK) << (loaded ? loaded->message() : "");
    std::this_thread::sleep_for(300ms);
    // The same room again, as text through the ROS 2 LoadWorld (left stopped), then played.
    std::ifstream room(source("worlds/small_room.xml"));
    std::stringstream xml;
    xml << room.rdbuf();
    ss::LoadWorld_Request_ load_text;
    load_text.resource_string(xml.str());
    const auto loaded_text =
        services.call<ss::LoadWorld_Request_PubSubType, ss::LoadWorld_Response_PubSubType>(
            "load_world", load_text);
    ASSERT_EQ(loaded_text.result().result(), 1) << loaded_text.result().error_message();
    ss::SetSimulationState_Request_ play;
    play.state().state(simulation_interfaces::msg::dds_::SimulationState_Constants::STATE_PLAYING);
    const auto played =
        services.call<ss::SetSimulationState_Request_PubSubType,
                      ss::SetSimulationState_Response_PubSubType>("set_simulation_state", play);
    ASSERT_EQ(played.result().result(), 1) << played.result().error_message();
    // Moved in the new world: the commands after a load run on it.
    const auto box = sv.call(supervisor::find_object("red_box"));
    ASSERT_TRUE(box && box->code() == mm::ERR_OK);
    r = sv.call(supervisor::set_linear_velocity(box->object_id(), {0.5, 0.0, 0.0}));
    ASSERT_TRUE(r && r->code() == mm::ERR_OK);
    std::this_thread::sleep_for(300ms);
  }
  macsim.signal(SIGINT);
  ASSERT_EQ(macsim.wait_for_exit(20s), 0) << macsim.output();
  // Counted as they ran: the eleven requests, spawn and play (loads are no commands), no picture,
  // no robot command.
  EXPECT_NE(macsim.output().find("commands run: supervisor 11 simulation 0 ros2_service 2 "
                                 "pictures 0 robot 0"),
            std::string::npos)
      << macsim.output();
  const Session session = read_session(path);
  std::map<std::string, int> operations;
  for (const auto& c : session.commands)
    ++operations[std::string(to_string(c.command.source)) + " " +
                 std::string(operation_name(c.command))];
  EXPECT_EQ(operations["simulation load_world"], 1);
  EXPECT_EQ(operations["simulation load_world_xml"], 1);
  EXPECT_EQ(operations["ros2_service set_simulation_state"], 0);  // playing changes no world
  EXPECT_EQ(operations["ros2_service spawn_entity"], 1);
  int supervisor_commands = 0;
  for (const auto& [name, count] : operations)
    if (name.rfind("supervisor ", 0) == 0) supervisor_commands += count;
  EXPECT_EQ(supervisor_commands, 9);  // 5 forces, density, save, restore, velocity: not the finds
  EXPECT_EQ(operations["supervisor add_force"], 5);
  EXPECT_EQ(operations["supervisor restore_snapshot"], 1);
  // The world loaded later is embedded when it was read, after the commands before its load.
  const auto room = std::find_if(session.files.begin(), session.files.end(), [](const auto& f) {
    return f.path == source("worlds/small_room.xml");
  });
  ASSERT_NE(room, session.files.end());
  EXPECT_GT(room->commands_before, 0u);
  const Replay replayed = replay(path);
  EXPECT_EQ(replayed.exit_code, 0) << replayed.output;
  EXPECT_EQ(hashes_equal(replayed.output), static_cast<int>(session.hashes.size()))
      << replayed.output;
}

// A world whose objects start inside each other, recorded with them kept where the file puts
// them (--keep-overlaps): the replay keeps them too, from the session's header alone, and
// meets every hash; the same records replayed as if they had been parted differ at once.
TEST(SessionReplay, ObjectsKeptInsideEachOtherAreKeptByTheReplay) {
  TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/kept.session";
  ChildProcess macsim({bin("macsim"), "--world", source("tests/worlds/overlapping_objects.xml"),
                       "--keep-overlaps", "--as-fast-as-possible", "--duration", "0.5", "--cameras",
                       "off", "--domain", std::to_string(unique_test_domain()), "--record-session",
                       path, "--session-hash-every", "50"});
  ASSERT_EQ(macsim.wait_for_exit(60s), 0) << macsim.output();
  std::ifstream in(path);
  std::stringstream whole;
  whole << in.rdbuf();
  const std::string text = whole.str();
  ASSERT_NE(text.find("\noverlaps kept\n"), std::string::npos) << text.substr(0, 200);

  const Replay kept = replay(path);
  EXPECT_EQ(kept.exit_code, 0) << kept.output;
  EXPECT_EQ(hashes_equal(kept.output), 11) << kept.output;  // steps 0, 50, ..., 500

  const std::string parted = dir.path() + "/parted.session";
  std::string changed = text;
  changed.replace(changed.find("overlaps kept"), 13, "overlaps parted");
  std::ofstream(parted) << changed;
  const Replay r = replay(parted);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(differs_at(r.output), 0u) << r.output;
}

// A session recorded by an earlier build and committed (tests/sessions/README.md): objects
// created, changed, pushed and destroyed by the supervisor, the door's switch triggered and its
// leaf moved, a snapshot saved and restored, the robot driven. A build that changes how the world
// holds its objects and doors must still replay it to every hash, in an empty folder.
TEST(SessionFixture, ARecordingOfAnEarlierBuildReplaysToEveryHash) {
  const std::string fixture = source("tests/sessions/supervised_demo_world.session");
  const Session session = read_session(fixture);
  EXPECT_GT(session.hashes.size(), 60u);
  std::map<std::string, int> operations;
  for (const auto& c : session.commands) ++operations[std::string(operation_name(c.command))];
  for (const char* operation : {"create_object", "set_pose", "set_box_size", "add_force",
                                "set_switch_triggered", "set_door_position", "restore_snapshot",
                                "destroy_object", "destroy_by_user_data", "twist"}) {
    EXPECT_GE(operations[operation], 1) << operation;
  }
  TempDir empty("macsim_fixture_");
  const Replay replayed = replay(fixture, empty.path());
  EXPECT_EQ(replayed.exit_code, 0) << replayed.output;
  EXPECT_EQ(hashes_equal(replayed.output), static_cast<int>(session.hashes.size()))
      << replayed.output;
}

}  // namespace
}  // namespace macsim::test
