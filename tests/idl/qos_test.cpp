// QoS families: deploy/dds/qos.xml, built into the library, decides them for every deployment;
// a deployment's or user's profile can change one by defining it.
// (ctest runs each test in a process of its own: Fast DDS keeps loaded profiles per process.)
#include "macsim/dds/qos.h"

#include <gtest/gtest.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <set>
#include <string>

#include "macsim/dds/participant.h"
#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

namespace fdds = eprosima::fastdds::dds;

TEST(QosFamilies, TheShippedProfileSetsEveryFamily) {
  dds::Participant p({unique_test_domain(), source("deploy/dds/localhost.xml"), "qos_test"});
  const auto command = dds::writer_qos(dds::QosFamily::Command, p.publisher());
  EXPECT_EQ(command.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(command.durability().kind, fdds::VOLATILE_DURABILITY_QOS);
  EXPECT_EQ(command.history().depth, 10);
  // no controller waits for its commands' acknowledgement (a step request names them): the
  // other families' heartbeat of 0.1 s, answered at once
  EXPECT_EQ(command.reliable_writer_qos().times.heartbeatPeriod.seconds, 0);
  EXPECT_EQ(command.reliable_writer_qos().times.heartbeatPeriod.nanosec, 100000000u);
  EXPECT_EQ(dds::reader_qos(dds::QosFamily::Command, p.subscriber())
                .reliable_reader_qos()
                .times.heartbeatResponseDelay.nanosec,
            0u);
  // no data sharing: a killed reader would hold a writer's samples until its lease ran out
  EXPECT_EQ(command.data_sharing().kind(), fdds::DataSharingKind::OFF);
  EXPECT_EQ(dds::reader_qos(dds::QosFamily::Command, p.subscriber()).data_sharing().kind(),
            fdds::DataSharingKind::OFF);
  // requests and replies: the command family's QoS
  const auto request = dds::writer_qos(dds::QosFamily::Request, p.publisher());
  EXPECT_EQ(request.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(request.history().depth, 10);
  EXPECT_EQ(request.data_sharing().kind(), fdds::DataSharingKind::OFF);
  // a lost request or reply is sent again within 0.1 s, not after Fast DDS's default 3 s
  EXPECT_EQ(request.reliable_writer_qos().times.heartbeatPeriod.nanosec, 100000000u);
  EXPECT_EQ(dds::reader_qos(dds::QosFamily::Request, p.subscriber()).data_sharing().kind(),
            fdds::DataSharingKind::OFF);
  const auto sensor = dds::reader_qos(dds::QosFamily::Sensor, p.subscriber());
  EXPECT_EQ(sensor.reliability().kind, fdds::BEST_EFFORT_RELIABILITY_QOS);
  EXPECT_EQ(sensor.history().depth, 5);
  // what a default ROS 2 subscription (reliable, volatile) matches: odometry, IMU, clock
  const auto state = dds::writer_qos(dds::QosFamily::State, p.publisher());
  EXPECT_EQ(state.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(state.durability().kind, fdds::VOLATILE_DURABILITY_QOS);
  EXPECT_EQ(state.history().depth, 100);  // a second of 100 Hz steps for a late reader
  EXPECT_EQ(state.resource_limits().max_samples_per_instance, 100);
  EXPECT_EQ(dds::reader_qos(dds::QosFamily::State, p.subscriber()).history().depth, 10);
  const auto latched = dds::writer_qos(dds::QosFamily::Latched, p.publisher());
  EXPECT_EQ(latched.durability().kind, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
  EXPECT_EQ(latched.history().depth, 1);
  EXPECT_EQ(latched.resource_limits().max_instances, 10000);  // one instance per object
}

TEST(QosFamilies, AUsersProfileChangesAFamily) {
  const std::string path =
      ::testing::TempDir() + "macsim_qos_profile_" + std::to_string(getpid()) + ".xml";
  std::ofstream(path) << R"(<?xml version="1.0"?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"><profiles>
  <data_writer profile_name="macsim_sensor">
    <topic><historyQos><kind>KEEP_LAST</kind><depth>7</depth></historyQos></topic>
    <qos><reliability><kind>RELIABLE</kind></reliability></qos>
  </data_writer>
</profiles></dds>)";
  dds::Participant p({unique_test_domain(), path, "qos_test"});
  const auto sensor = dds::writer_qos(dds::QosFamily::Sensor, p.publisher());
  EXPECT_EQ(sensor.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(sensor.history().depth, 7);
  // A family the profile does not name keeps the built-in policies.
  const auto latched = dds::writer_qos(dds::QosFamily::Latched, p.publisher());
  EXPECT_EQ(latched.durability().kind, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
  const auto state = dds::writer_qos(dds::QosFamily::State, p.publisher());
  EXPECT_EQ(state.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
  EXPECT_EQ(state.history().depth, 100);
  EXPECT_EQ(dds::reader_qos(dds::QosFamily::State, p.subscriber()).history().depth, 10);
  // The profile names the sensor writer only: the sensor reader stays the built-in one.
  const auto sensor_reader = dds::reader_qos(dds::QosFamily::Sensor, p.subscriber());
  EXPECT_EQ(sensor_reader.reliability().kind, fdds::BEST_EFFORT_RELIABILITY_QOS);
  EXPECT_EQ(sensor_reader.history().depth, 5);
  std::remove(path.c_str());
}

/// The data writer and reader profile names an XML profile file defines.
std::set<std::string> qos_profiles_of(const std::string& path) {
  tinyxml2::XMLDocument document;
  EXPECT_EQ(document.LoadFile(path.c_str()), tinyxml2::XML_SUCCESS) << path;
  std::set<std::string> names;
  const auto* root = document.RootElement();
  const auto* profiles = root ? root->FirstChildElement("profiles") : nullptr;
  for (const auto* e = profiles ? profiles->FirstChildElement() : nullptr; e;
       e = e->NextSiblingElement()) {
    const std::string kind = e->Name();
    if (kind == "data_writer" || kind == "data_reader") {
      names.insert(kind + " " + e->Attribute("profile_name"));
    }
  }
  return names;
}

TEST(QosFamilies, AreWrittenOnceInQosXmlAndNoDeploymentRepeatsThem) {
  std::set<std::string> expected;
  for (auto family :
       {dds::QosFamily::Command, dds::QosFamily::Sensor, dds::QosFamily::State,
        dds::QosFamily::Latched, dds::QosFamily::Request, dds::QosFamily::LockstepSensor}) {
    expected.insert(std::string("data_writer ") + dds::profile_name(family));
    expected.insert(std::string("data_reader ") + dds::profile_name(family));
  }
  EXPECT_EQ(qos_profiles_of(source("deploy/dds/qos.xml")), expected);
  for (const char* deployment : {"localhost", "network", "service", "service_localhost"}) {
    EXPECT_EQ(qos_profiles_of(source("deploy/dds/" + std::string(deployment) + ".xml")),
              std::set<std::string>{})
        << deployment << ".xml repeats a QoS family of qos.xml";
  }
}

}  // namespace
}  // namespace macsim::test
