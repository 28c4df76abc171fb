// The supervisor over real DDS: a client process calls operations on macsim, a second
// participant sees their effect on the world state topic; bad requests get clear errors.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>

#include "macsim/client/supervisor_client.h"
#include "macsim/client/world_state.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/topics.h"
#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;
using client::SupervisorClient;

using WorldObserver = client::WorldStateClient;

class Supervisor : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = unique_test_domain();
    macsim_ = std::make_unique<ChildProcess>(std::vector<std::string>{
        bin("macsim"), "--world", source("worlds/DemoWorld_v1.xml"), "--domain",
        std::to_string(domain_), "--cameras", "off"});
    ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
    participant_ = std::make_unique<dds::Participant>(dds::ParticipantOptions{domain_, "", "supervisor_test"});
    client_ = std::make_unique<SupervisorClient>(*participant_);
    ASSERT_TRUE(client_->wait_for_server(20s));
  }
  void TearDown() override {
    client_.reset();
    participant_.reset();
    macsim_->signal(SIGTERM);
    EXPECT_EQ(macsim_->wait_for_exit(10s), 0) << macsim_->output();
  }
  SupervisorClient::Reply call(const SupervisorClient::Request& r) {
    auto reply = client_->call(r);
    EXPECT_TRUE(reply.has_value()) << "no reply";
    return reply.value_or(SupervisorClient::Reply{});
  }

  int domain_ = 0;
  std::unique_ptr<ChildProcess> macsim_;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<SupervisorClient> client_;
};

TEST_F(Supervisor, CreateMoveAndDestroyAreSeenOnTheWorldState) {
  WorldObserver observer(*participant_);
  // A late joiner gets every object of the loaded world.
  ASSERT_TRUE(observer.wait([](const auto& objects, const auto&) { return objects.size() == 24; }));

  auto create = SupervisorClient::request(mm::OP_CREATE_OBJECT);
  mm::Component_ box;
  box.shape(0);
  box.size({0.1, 0.1, 0.1});
  box.pose().orientation().w(1.0);
  box.color({0.2f, 0.9f, 0.2f, 1.0f});
  create.object().components().push_back(box);
  create.object().portable(true);
  create.object().name("supervised_box");
  create.object().pose().position(dds::point(-0.5, 0.3, 0.5));
  create.object().pose().orientation().w(1.0);
  const auto created = call(create);
  ASSERT_EQ(created.code(), mm::ERR_OK) << created.message();
  const uint32_t id = created.object_id();
  // It falls and lands on the floor: the observer sees it resting at z = 0.05.
  EXPECT_TRUE(observer.wait([id](const auto& objects, const auto&) {
    auto o = objects.find(id);
    return o != objects.end() && std::fabs(o->second.object().pose().position().z() - 0.05) < 0.003;
  }));

  const auto moved = call(SupervisorClient::request(mm::OP_SET_POSITION, id, {-0.5, -0.6, 0.05}));
  ASSERT_EQ(moved.code(), mm::ERR_OK) << moved.message();
  EXPECT_TRUE(observer.wait([id](const auto& objects, const auto&) {
    auto o = objects.find(id);
    return o != objects.end() && std::fabs(o->second.object().pose().position().y() + 0.6) < 0.01;
  }));

  const auto recolored = call(SupervisorClient::request(mm::OP_SET_COLOR, id, {1, 0, 0, 1}));
  ASSERT_EQ(recolored.code(), mm::ERR_OK);
  EXPECT_TRUE(observer.wait([id](const auto& objects, const auto&) {
    auto o = objects.find(id);
    return o != objects.end() && o->second.object().components()[0].color()[0] == 1.0f;
  }));

  ASSERT_EQ(call(SupervisorClient::request(mm::OP_DESTROY_OBJECT, id)).code(), mm::ERR_OK);
  EXPECT_TRUE(observer.wait([id](const auto& objects, const auto& gone) {
    return !objects.count(id) && gone.count(id);  // the instance was disposed
  }));
}

TEST_F(Supervisor, BadRequestsGetClearErrorsAndChangeNothing) {
  const auto list = call(SupervisorClient::request(mm::OP_LIST_OBJECTS));
  ASSERT_EQ(list.count(), 24);
  const uint32_t box = [&] {
    auto find = SupervisorClient::request(mm::OP_FIND_OBJECT);
    find.name("environment_01/box_red_small");
    return call(find).object_id();
  }();
  ASSERT_NE(box, 0u);
  const auto before = call(SupervisorClient::request(mm::OP_GET_OBJECT, box)).object();

  const auto unknown = call(SupervisorClient::request(mm::OP_SET_POSITION, 999999, {0, 0, 1}));
  EXPECT_EQ(unknown.code(), mm::ERR_UNKNOWN_OBJECT);
  EXPECT_NE(unknown.message().find("999999"), std::string::npos);
  const auto nan = call(SupervisorClient::request(mm::OP_SET_POSITION, box, {std::nan(""), 0, 1}));
  EXPECT_EQ(nan.code(), mm::ERR_INVALID_ARGUMENT);
  const auto negative = call(SupervisorClient::request(mm::OP_SET_BOX_SIZE, box, {0.1, -1, 0.1}));
  EXPECT_EQ(negative.code(), mm::ERR_INVALID_ARGUMENT);
  const auto wrong = call(SupervisorClient::request(mm::OP_SET_SPHERE_SIZE, box, {0.1}));
  EXPECT_EQ(wrong.code(), mm::ERR_WRONG_GEOMETRY);
  auto texture = SupervisorClient::request(mm::OP_SET_TEXTURE, box);
  texture.index(-1);
  texture.text("/nonexistent/picture.bmp");
  EXPECT_EQ(call(texture).code(), mm::ERR_BAD_TEXTURE);
  const auto penetrate = call(SupervisorClient::request(mm::OP_SET_POSITION, box, {0.0, -0.3, 0.2}));
  EXPECT_EQ(penetrate.code(), mm::ERR_PENETRATION);
  EXPECT_EQ(call(SupervisorClient::request(12345)).code(), mm::ERR_UNKNOWN_OPERATION);

  // Nothing changed: the same objects, the box where it was (at rest), same size and colour.
  const auto still = call(SupervisorClient::request(mm::OP_LIST_OBJECTS));
  EXPECT_EQ(still.object_ids(), list.object_ids());
  const auto after = call(SupervisorClient::request(mm::OP_GET_OBJECT, box)).object();
  EXPECT_NEAR(after.pose().position().x(), before.pose().position().x(), 1e-6);
  EXPECT_NEAR(after.pose().position().y(), before.pose().position().y(), 1e-6);
  EXPECT_EQ(after.components()[0].size(), before.components()[0].size());
  EXPECT_EQ(after.components()[0].texture(), before.components()[0].texture());
  EXPECT_TRUE(macsim_->running());
}

TEST_F(Supervisor, DoorsResetAndSnapshotsOverDds) {
  ASSERT_EQ(call(SupervisorClient::request(mm::OP_DOOR_COUNT)).count(), 1);
  auto trigger = SupervisorClient::request(mm::OP_SET_SWITCH_TRIGGERED);
  trigger.index(0);
  trigger.flag(true);
  ASSERT_EQ(call(trigger).code(), mm::ERR_OK);
  auto get_door = SupervisorClient::request(mm::OP_GET_DOOR);
  get_door.index(0);
  bool opened = false;
  for (int i = 0; i < 100 && !opened; ++i) {
    opened = call(get_door).door().gap() == 2;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_TRUE(opened);
  auto reset = SupervisorClient::request(mm::OP_RESET);
  reset.index(2);  // everything
  ASSERT_EQ(call(reset).code(), mm::ERR_OK);
  const auto door = call(get_door).door();
  EXPECT_LT(door.opening(), 0.05);
  EXPECT_FALSE(door.virtually_triggered());
}

}  // namespace
}  // namespace macsim::test
