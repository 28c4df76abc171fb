// The files a remote participant can make macsim read: every path class (outside a root, `..`,
// a symbolic link leaving a root, a device, /proc, a FIFO, a missing file outside a root and
// one inside) through the supervisor, the simulation control and the ROS 2 services. Outside
// a root: one answer, the same whether the file exists; nothing opened (a FIFO a read would
// block on stays unopened); the state hash unchanged. Files outside are valid worlds,
// environments and textures, so that a read that should not happen would succeed.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>

#include "macsim/client/supervisor_client.h"
#include "macsim/dds/ros2_service.h"
#include "macsim/msg/simulation_interfacesPubSubTypes.h"
#include "support/child_process.h"
#include "support/open_watch.h"
#include "support/ros2_service_calls.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
namespace mm = macsim_msgs::msg::dds_;
namespace ss = simulation_interfaces::srv::dds_;
namespace supervisor = client::supervisor;

const char* kOutsideWords = "is outside the folders this simulator reads files from";

/// The answer with the path taken out: what is left must not depend on the file.
std::string without(std::string answer, const std::string& path) {
  for (auto at = answer.find(path); at != std::string::npos; at = answer.find(path)) {
    answer.erase(at, path.size());
  }
  return answer;
}

class DataRoots : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::make_unique<TempDir>("macsim_roots_");
    const fs::path base = dir_->path();
    root_ = base / "root";
    outside_ = base / "outside";
    fs::create_directories(root_);
    fs::create_directories(outside_);
    fs::copy_file(source("worlds/small_room.xml"), root_ / "room.xml");
    fs::copy_file(source("worlds/small_room.xml"), outside_ / "room.xml");
    const std::string texture = source("worlds/DemoEnvironment_v1/textures/checker.bmp");
    fs::copy_file(texture, root_ / "checker.bmp");
    fs::copy_file(texture, outside_ / "checker.bmp");
    for (const fs::path& folder : {root_, outside_}) {
      std::ofstream(folder / "crate.xml")
          << "<ENVIRONMENT><OBJECT><ID>box</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE>"
             "<DIMS>0.2,0.2,0.2</DIMS><POS>0,2,0.1</POS></OBJECT></ENVIRONMENT>";
    }
    fs::create_symlink(outside_ / "room.xml", root_ / "link_room.xml");
    fs::create_symlink(outside_ / "crate.xml", root_ / "link_crate.xml");
    fs::create_symlink(outside_ / "checker.bmp", root_ / "link_checker.bmp");
    ASSERT_EQ(::mkfifo((root_ / "fifo.xml").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo((outside_ / "fifo.xml").c_str(), 0600), 0);
    fifo_watch_ = std::make_unique<OpenWatch>(
        std::vector<std::string>{(root_ / "fifo.xml").string(), (outside_ / "fifo.xml").string()});
    ASSERT_TRUE(fifo_watch_->watching());

    domain_ = unique_test_domain();
    macsim_ = std::make_unique<ChildProcess>(std::vector<std::string>{
        bin("macsim"), "--world", (root_ / "room.xml").string(), "--domain",
        std::to_string(domain_), "--lockstep", "--cameras", "off"});
    ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
    participant_ =
        std::make_unique<dds::Participant>(dds::ParticipantOptions{domain_, "", "roots_test"});
    supervisor_ = std::make_unique<client::SupervisorClient>(*participant_);
    control_ = std::make_unique<client::SimulationClient>(*participant_);
    services_ = std::make_unique<Ros2ServiceCalls>(*participant_);
  }
  void TearDown() override {
    control_.reset();
    supervisor_.reset();
    services_.reset();
    participant_.reset();
    if (!macsim_) return;
    macsim_->signal(SIGTERM);
    EXPECT_EQ(macsim_->wait_for_exit(10s), 0) << macsim_->output();
  }

  /// Paths outside the root, each with a twin that does not exist (same folder, other name)
  /// where one can be made: the answers of the twins must be the same.
  struct Outside {
    std::string what, path;
  };
  std::vector<Outside> outside(const std::string& file) const {
    const std::string dotdot = (root_ / ".." / "outside" / file).string();
    return {{"outside a root", (outside_ / file).string()},
            {"missing outside a root", (outside_ / ("missing_" + file)).string()},
            {"missing in a folder outside", (outside_ / "nofolder" / file).string()},
            {"..", dotdot},
            {"a symbolic link leaving the root", (root_ / ("link_" + file)).string()},
            {"a device", "/dev/zero"},
            {"/proc", "/proc/self/environ"},
            {"a FIFO outside", (outside_ / "fifo.xml").string()}};
  }
  /// True if anyone (macsim included) opened one of the FIFOs since the last look.
  bool fifo_opened() { return fifo_watch_->opened(); }
  uint64_t state_hash() { return supervise(supervisor::state_hash()).hash(); }
  mm::SupervisorReply_ supervise(const mm::SupervisorRequest_& request) {
    auto reply = supervisor_->call(request, 20s);
    EXPECT_TRUE(reply.has_value()) << "no supervisor reply";
    return reply.value_or(mm::SupervisorReply_{});
  }
  mm::SimulationReply_ load(const std::string& file) {
    auto request = client::SimulationClient::request(mm::SIM_LOAD_WORLD);
    request.world_file(file);
    auto reply = control_->call(request, 30s);
    EXPECT_TRUE(reply.has_value()) << "no simulation reply";
    return reply.value_or(mm::SimulationReply_{});
  }
  template <class Req, class Resp>
  typename Resp::type service(const std::string& name, const typename Req::type& request) {
    return services_->call<Req, Resp>(name, request);
  }
  ss::LoadWorld_Response_ ros_load(const std::string& uri) {
    ss::LoadWorld_Request_ q;
    q.uri(uri);
    return service<ss::LoadWorld_Request_PubSubType, ss::LoadWorld_Response_PubSubType>(
        "load_world", q);
  }
  ss::SpawnEntity_Response_ ros_spawn(const std::string& uri) {
    ss::SpawnEntity_Request_ q;
    q.name("spawned");
    q.uri(uri);
    q.initial_pose().pose().orientation().w(1);
    return service<ss::SpawnEntity_Request_PubSubType, ss::SpawnEntity_Response_PubSubType>(
        "spawn_entity", q);
  }

  /// Checks one channel's answers to every path class: `answer` returns (code, message), the
  /// code `ok` meaning done.
  void expect_one_answer(const std::string& channel, const std::string& file, int ok,
                         const std::function<std::pair<int, std::string>(const std::string&)>&
                             answer) {
    const uint64_t before = state_hash();
    std::string first;
    int first_code = ok;
    for (const Outside& o : outside(file)) {
      const auto [code, message] = answer(o.path);
      EXPECT_NE(code, ok) << channel << ", " << o.what << ": " << message;
      if (first_code == ok) first_code = code;
      EXPECT_EQ(code, first_code) << channel << ", " << o.what << ": " << message;
      EXPECT_NE(message.find(kOutsideWords), std::string::npos)
          << channel << ", " << o.what << ": " << message;
      EXPECT_EQ(message.find("exist"), std::string::npos)
          << channel << ", " << o.what << ": " << message;
      const std::string shape = without(message, o.path);
      if (first.empty()) first = shape;
      EXPECT_EQ(shape, first) << channel << ", " << o.what << " answers otherwise";
    }
    // Inside the root: a FIFO is refused unopened, a missing file is said to be missing.
    const auto [fifo_code, fifo_message] = answer((root_ / "fifo.xml").string());
    EXPECT_NE(fifo_code, ok);
    EXPECT_NE(fifo_message.find("is not a regular file"), std::string::npos)
        << channel << ": " << fifo_message;
    const auto [missing_code, missing_message] = answer((root_ / ("missing_" + file)).string());
    EXPECT_NE(missing_code, ok);
    EXPECT_EQ(missing_message.find(kOutsideWords), std::string::npos) << missing_message;
    EXPECT_FALSE(fifo_opened()) << channel << " opened a FIFO";
    EXPECT_EQ(state_hash(), before) << channel << " changed the world";
  }

  std::unique_ptr<TempDir> dir_;
  fs::path root_, outside_;
  std::unique_ptr<OpenWatch> fifo_watch_;
  int domain_ = 0;
  std::unique_ptr<ChildProcess> macsim_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<client::SupervisorClient> supervisor_;
  std::unique_ptr<client::SimulationClient> control_;
  std::unique_ptr<Ros2ServiceCalls> services_;
};

TEST_F(DataRoots, TheSupervisorReadsNoFileOutsideTheRoots) {
  const uint32_t box = supervise(supervisor::find_object("red_box")).object_id();
  ASSERT_NE(box, 0u);
  expect_one_answer("set_texture", "checker.bmp", mm::ERR_OK, [&](const std::string& path) {
    const auto r = supervise(supervisor::set_texture(box, path));
    return std::pair{int(r.code()), r.message()};
  });
  expect_one_answer("import_environment", "crate.xml", mm::ERR_OK, [&](const std::string& path) {
    const auto r = supervise(supervisor::import_environment(path, "crate", {0, 2, 0}));
    return std::pair{int(r.code()), r.message()};
  });
  EXPECT_EQ(supervise(supervisor::set_texture(box, (outside_ / "checker.bmp").string())).code(),
            mm::ERR_BAD_FILE);
  // Inside the root the same requests work.
  EXPECT_EQ(supervise(supervisor::set_texture(box, (root_ / "checker.bmp").string())).code(),
            mm::ERR_OK);
  EXPECT_EQ(
      supervise(supervisor::import_environment((root_ / "crate.xml").string(), "crate", {0, 2, 0}))
          .code(),
      mm::ERR_OK);
}

TEST_F(DataRoots, TheSimulationControlLoadsNoWorldOutsideTheRoots) {
  expect_one_answer("load_world", "room.xml", mm::ERR_OK, [&](const std::string& path) {
    const auto r = load(path);
    return std::pair{int(r.code()), r.message()};
  });
  EXPECT_EQ(load((root_ / "room.xml").string()).code(), mm::ERR_OK);
  EXPECT_NE(macsim_->output().find("requests may name files under: " +
                                   fs::canonical(root_).string()),
            std::string::npos)
      << macsim_->output();
}

TEST_F(DataRoots, TheRos2ServicesReadNoFileOutsideTheRoots) {
  namespace rc = simulation_interfaces::msg::dds_::Result_Constants;
  expect_one_answer("LoadWorld", "room.xml", rc::RESULT_OK, [&](const std::string& path) {
    const auto r = ros_load("file://" + path);
    return std::pair{int(r.result().result()), r.result().error_message()};
  });
  expect_one_answer("SpawnEntity", "crate.xml", rc::RESULT_OK, [&](const std::string& path) {
    const auto r = ros_spawn("file://" + path);
    return std::pair{int(r.result().result()), r.result().error_message()};
  });
  // The lists hold what lies under the roots only; a folder outside is named, not searched.
  ss::GetAvailableWorlds_Request_ worlds;
  worlds.additional_sources({outside_.string(), (root_ / ".." / "outside").string(), "/etc"});
  worlds.continue_on_error(true);
  const auto available =
      service<ss::GetAvailableWorlds_Request_PubSubType, ss::GetAvailableWorlds_Response_PubSubType>(
          "get_available_worlds", worlds);
  bool room = false;
  for (const auto& w : available.worlds()) {
    const std::string uri = w.world_resource().uri();
    EXPECT_EQ(uri.find(outside_.string()), std::string::npos) << uri;
    EXPECT_EQ(uri.find("link_room"), std::string::npos) << uri;
    room = room || uri == "file://" + (fs::canonical(root_) / "room.xml").string();
  }
  EXPECT_TRUE(room) << "the world's own folder is not listed";
  EXPECT_NE(available.result().error_message().find("outside the data roots"), std::string::npos)
      << available.result().error_message();
  ss::GetSpawnables_Request_ spawnables;
  spawnables.sources({outside_.string()});
  // The response kept in a variable: a range-for over a member of a temporary would read it
  // after it is gone.
  const auto listed =
      service<ss::GetSpawnables_Request_PubSubType, ss::GetSpawnables_Response_PubSubType>(
          "get_spawnables", spawnables);
  for (const auto& s : listed.spawnables()) {
    EXPECT_EQ(s.uri().find(outside_.string()), std::string::npos) << s.uri();
  }
  EXPECT_EQ(ros_spawn("file://" + (root_ / "crate.xml").string()).result().result(),
            rc::RESULT_OK);
}

TEST_F(DataRoots, DataPathAddsAFolder) {
  // A second macsim given --data-path reads the folder the first one refused.
  TearDown();
  macsim_.reset();
  domain_ = unique_test_domain();
  macsim_ = std::make_unique<ChildProcess>(std::vector<std::string>{
      bin("macsim"), "--world", (root_ / "room.xml").string(), "--domain", std::to_string(domain_),
      "--lockstep", "--cameras", "off", "--data-path", outside_.string()});
  ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
  participant_ =
      std::make_unique<dds::Participant>(dds::ParticipantOptions{domain_, "", "roots_test"});
  supervisor_ = std::make_unique<client::SupervisorClient>(*participant_);
  control_ = std::make_unique<client::SimulationClient>(*participant_);
  const auto imported =
      supervise(supervisor::import_environment((outside_ / "crate.xml").string(), "crate", {0, 2, 0}));
  EXPECT_EQ(imported.code(), mm::ERR_OK) << imported.message();
  EXPECT_EQ(load((outside_ / "room.xml").string()).code(), mm::ERR_OK);
  // Still no device, no /proc, no FIFO.
  EXPECT_EQ(load("/proc/self/environ").code(), mm::ERR_BAD_FILE);
  EXPECT_NE(load((outside_ / "fifo.xml").string()).message().find("is not a regular file"),
            std::string::npos);
  EXPECT_FALSE(fifo_opened());
  // A --data-path that is no folder is a usage error, before anything is served.
  ChildProcess bad({bin("macsim"), "--world", (root_ / "room.xml").string(), "--domain",
                    std::to_string(domain_), "--cameras", "off", "--data-path",
                    (root_ / "checker.bmp").string()});
  EXPECT_EQ(bad.wait_for_exit(30s), 2) << bad.output();
  EXPECT_NE(bad.output().find("is no folder"), std::string::npos) << bad.output();
}

}  // namespace
}  // namespace macsim::test
