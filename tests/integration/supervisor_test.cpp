// The supervisor over real DDS: a client process calls operations on macsim, a second
// participant sees their effect on the world state topic; bad requests get clear errors.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <thread>

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
namespace supervisor = client::supervisor;

using WorldObserver = client::WorldStateClient;

/// Bytes on the wire under another type's name: what a broken or hostile peer could send.
struct RawSample {
  std::string bytes;
};
template <const char* kName>
class RawType : public eprosima::fastdds::dds::TopicDataType {
 public:
  using type = RawSample;
  RawType() {
    setName(kName);
    m_typeSize = 1024;
    m_isGetKeyDefined = false;
  }
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const std::string& bytes = static_cast<RawSample*>(data)->bytes;
    std::copy(bytes.begin(), bytes.end(), payload->data);
    payload->length = uint32_t(bytes.size());
    return true;
  }
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t*, void*) override { return false; }
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override {
    const auto n = uint32_t(static_cast<RawSample*>(data)->bytes.size());
    return [n] { return n; };
  }
  void* createData() override { return new RawSample; }
  void deleteData(void* data) override { delete static_cast<RawSample*>(data); }
  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
};
constexpr char kSupervisorRequestType[] = "macsim_msgs::msg::dds_::SupervisorRequest_";
constexpr char kSimulationRequestType[] = "macsim_msgs::msg::dds_::SimulationRequest_";

class Supervisor : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = unique_test_domain();
    macsim_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{bin("macsim"), "--world", source("worlds/DemoWorld_v1.xml"),
                                 "--domain", std::to_string(domain_), "--cameras", "off"});
    ASSERT_TRUE(macsim_->wait_for_output("stepping", 30s)) << macsim_->output();
    participant_ =
        std::make_unique<dds::Participant>(dds::ParticipantOptions{domain_, "", "supervisor_test"});
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

  mm::Object_ object;
  mm::Component_ box;
  box.shape(mm::SHAPE_BOX);
  box.size({0.1, 0.1, 0.1});
  box.pose().orientation().w(1.0);
  box.color({0.2f, 0.9f, 0.2f, 1.0f});
  object.components().push_back(box);
  object.portable(true);
  object.name("supervised_box");
  object.pose().position(dds::point(-0.5, 0.3, 0.5));
  object.pose().orientation().w(1.0);
  const auto created = call(supervisor::create_object(object));
  ASSERT_EQ(created.code(), mm::ERR_OK) << created.message();
  const uint32_t id = created.object_id();
  // It falls and lands on the floor: the observer sees it resting at z = 0.05.
  EXPECT_TRUE(observer.wait([id](const auto& objects, const auto&) {
    auto o = objects.find(id);
    return o != objects.end() && std::fabs(o->second.object().pose().position().z() - 0.05) < 0.003;
  }));

  const auto moved = call(supervisor::set_position(id, {-0.5, -0.6, 0.05}));
  ASSERT_EQ(moved.code(), mm::ERR_OK) << moved.message();
  EXPECT_TRUE(observer.wait([id](const auto& objects, const auto&) {
    auto o = objects.find(id);
    return o != objects.end() && std::fabs(o->second.object().pose().position().y() + 0.6) < 0.01;
  }));

  const auto recolored = call(supervisor::set_color(id, {1, 0, 0, 1}));
  ASSERT_EQ(recolored.code(), mm::ERR_OK);
  EXPECT_TRUE(observer.wait([id](const auto& objects, const auto&) {
    auto o = objects.find(id);
    return o != objects.end() && o->second.object().components()[0].color()[0] == 1.0f;
  }));

  ASSERT_EQ(call(supervisor::destroy_object(id)).code(), mm::ERR_OK);
  EXPECT_TRUE(observer.wait([id](const auto& objects, const auto& gone) {
    return !objects.count(id) && gone.count(id);  // the instance was disposed
  }));
}

TEST_F(Supervisor, BadRequestsGetClearErrorsAndChangeNothing) {
  const auto list = call(supervisor::list_objects());
  ASSERT_EQ(list.count(), 24);
  const uint32_t box = [&] {
    return call(supervisor::find_object("environment_01/box_red_small")).object_id();
  }();
  ASSERT_NE(box, 0u);
  const auto before = call(supervisor::get_object(box)).object();

  const auto unknown = call(supervisor::set_position(999999, {0, 0, 1}));
  EXPECT_EQ(unknown.code(), mm::ERR_UNKNOWN_OBJECT);
  EXPECT_NE(unknown.message().find("999999"), std::string::npos);
  const auto nan = call(supervisor::set_position(box, {std::nan(""), 0, 1}));
  EXPECT_EQ(nan.code(), mm::ERR_INVALID_ARGUMENT);
  const auto negative = call(supervisor::set_box_size(box, 0, {0.1, -1, 0.1}));
  EXPECT_EQ(negative.code(), mm::ERR_INVALID_ARGUMENT);
  const auto wrong = call(supervisor::set_sphere_size(box, 0, 0.1));
  EXPECT_EQ(wrong.code(), mm::ERR_WRONG_GEOMETRY);
  EXPECT_EQ(call(supervisor::set_texture(box, source("worlds/no_such_picture.bmp"))).code(),
            mm::ERR_BAD_TEXTURE);
  EXPECT_EQ(call(supervisor::set_texture(box, "/nonexistent/picture.bmp")).code(),
            mm::ERR_BAD_FILE);  // outside the data roots
  const auto penetrate = call(supervisor::set_position(box, {0.0, -0.3, 0.2}));
  EXPECT_EQ(penetrate.code(), mm::ERR_PENETRATION);
  auto unknown_operation = supervisor::list_objects();
  unknown_operation.operation()._d() = 12345;  // a code this server does not know
  EXPECT_EQ(call(unknown_operation).code(), mm::ERR_UNKNOWN_OPERATION);

  // Nothing changed: the same objects, the box where it was (at rest), same size and colour.
  const auto still = call(supervisor::list_objects());
  EXPECT_EQ(still.object_ids(), list.object_ids());
  const auto after = call(supervisor::get_object(box)).object();
  EXPECT_NEAR(after.pose().position().x(), before.pose().position().x(), 1e-6);
  EXPECT_NEAR(after.pose().position().y(), before.pose().position().y(), 1e-6);
  EXPECT_EQ(after.components()[0].size(), before.components()[0].size());
  EXPECT_EQ(after.components()[0].texture(), before.components()[0].texture());
  EXPECT_TRUE(macsim_->running());
}

TEST_F(Supervisor, BrokenPacketsOnTheRequestTopicsAreDroppedAndMacsimServesOn) {
  // A peer sends bytes under the request types' names: a bad CDR encapsulation, a union
  // discriminator of no member, lengths past the end, nothing at all.
  dds::Participant raw_peer({domain_, "", "broken_peer"});
  dds::Writer<RawType<kSupervisorRequestType>> supervisor_raw(
      raw_peer, dds::topics::kSupervisorRequest, dds::QosFamily::Command);
  dds::Writer<RawType<kSimulationRequestType>> simulation_raw(
      raw_peer, dds::topics::kSimulationRequest, dds::QosFamily::Command);
  for (int i = 0; i < 100 && (supervisor_raw.matched() == 0 || simulation_raw.matched() == 0); ++i)
    std::this_thread::sleep_for(50ms);
  ASSERT_EQ(supervisor_raw.matched(), 1);
  const std::vector<std::string> broken{
      std::string("\x07\x01\x00\x00", 4) + std::string(40, '\xff'),  // bad encapsulation
      std::string("\x00\x01\x00\x00", 4) + std::string(60, '\xff'),  // huge lengths
      std::string("\x00\x01\x00\x00\x08\x00\x00\x00" "abc", 11),      // truncated string
      std::string("\x00\x01\x00\x00", 4),                            // nothing after the header
      std::string(3, '\x00')};
  for (const auto& bytes : broken) {
    EXPECT_TRUE(supervisor_raw.write(RawSample{bytes}));
    EXPECT_TRUE(simulation_raw.write(RawSample{bytes}));
  }
  EXPECT_TRUE(supervisor_raw.wait_acknowledged(5s));
  EXPECT_TRUE(simulation_raw.wait_acknowledged(5s));
  EXPECT_TRUE(macsim_->running()) << macsim_->output();
  EXPECT_EQ(call(supervisor::list_objects()).count(), 24);  // and it still answers
}

TEST_F(Supervisor, DoorsResetAndSnapshotsOverDds) {
  ASSERT_EQ(call(supervisor::door_count()).count(), 1);
  ASSERT_EQ(call(supervisor::set_switch_triggered(0, true)).code(), mm::ERR_OK);
  const auto get_door = supervisor::get_door(0);
  bool opened = false;
  for (int i = 0; i < 100 && !opened; ++i) {
    opened = call(get_door).door().gap() == mm::GAP_OPEN;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_TRUE(opened);
  ASSERT_EQ(call(supervisor::reset(mm::RESET_EVERYTHING)).code(), mm::ERR_OK);
  const auto door = call(get_door).door();
  EXPECT_LT(door.opening(), 0.05);
  EXPECT_FALSE(door.virtually_triggered());
}

}  // namespace
}  // namespace macsim::test
