// CAN transports: the userspace UDP bus carries frames both ways unchanged; SocketCAN is tried
// for real and skipped, with the reason, where the kernel has no CAN support or no can0.
#include <gtest/gtest.h>

#include "macsim/kurt/kurt_can.h"
#include "support/test_domain.h"

namespace macsim::kurt {
namespace {

using namespace std::chrono_literals;

TEST(CanTransport, UserspaceBusCarriesFramesBothWays) {
  // Below Fast DDS ports (7400 + 250 d), the ephemeral range and kurt_adapter_test (5200+).
  const int port = 6000 + 2 * test::unique_test_domain();
  auto adapter = open_can("udp:" + std::to_string(port) + ":" + std::to_string(port + 1));
  auto robot = open_can("udp:" + std::to_string(port + 1) + ":" + std::to_string(port));
  ASSERT_TRUE(adapter->send(encode_speed_cm({0.3, -0.3})));
  const auto got = robot->receive(1000ms);
  ASSERT_TRUE(got);
  EXPECT_EQ(*got, encode_speed_cm({0.3, -0.3}));
  ASSERT_TRUE(robot->send(encode_encoder({-200, 200})));
  EXPECT_EQ(adapter->receive(1000ms), encode_encoder({-200, 200}));
  EXPECT_FALSE(adapter->receive(50ms));  // nothing more
}

TEST(CanTransport, BadBusNamesAreRefusedWithTheExpectedForm) {
  try {
    open_can("serial:/dev/ttyUSB0");
    FAIL();
  } catch (const CanError& e) {
    EXPECT_NE(std::string(e.what()).find("socketcan:IFACE"), std::string::npos) << e.what();
  }
  EXPECT_THROW(open_can("udp:0:70000"), CanError);
}

TEST(CanTransport, SocketCanOnCan0) {
  std::unique_ptr<CanTransport> can;
  try {
    can = open_socketcan("can0");
  } catch (const CanError& e) {
    const std::string why = e.what();
    // Only the two reasons a machine without the robot has are a skip; anything else fails.
    ASSERT_TRUE(why.find("no CAN support") != std::string::npos ||
                why.find("no CAN interface") != std::string::npos)
        << why;
    GTEST_SKIP() << why;
  }
  // A CAN interface exists (the robot, or vcan): a frame we send is accepted.
  EXPECT_TRUE(can->send(encode_speed_cm({0.0, 0.0})));
}

}  // namespace
}  // namespace macsim::kurt
