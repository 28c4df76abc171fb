// Fuzzes the KURT's CAN side: datagrams of the userspace bus decoded into frames, every decoder
// of the protocol, and the driver's state machine fed those frames between commands (cmd_vel,
// wheel speeds, rotunit speed: any double, NaN and infinity included) and clock ticks. After each
// record: the odometry is finite with its yaw in (-pi, pi], ranges are finite, the gyro's yaw
// lies in [-pi, pi], and every control frame the driver would send decodes as a command.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "finding.h"
#include "fuzz_input.h"
#include "macsim/kurt/kurt_can.h"
#include "macsim/kurt/kurt_driver.h"

namespace {

using macsim::fuzz::finding;

/// The i-th double of a record's bytes (zero past the end).
double number(std::string_view bytes, std::size_t i) {
  double value = 0.0;
  if (bytes.size() >= (i + 1) * sizeof value) std::memcpy(&value, bytes.data() + i * 8, 8);
  return value;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace macsim::kurt;
  KurtDriver driver;
  double now = 0.0;
  for (const auto& record :
       macsim::fuzz::split_records({reinterpret_cast<const char*>(data), size})) {
    switch (record.kind % 5) {
      case 0: {  // a datagram off the bus
        const auto frame = from_datagram(reinterpret_cast<const uint8_t*>(record.bytes.data()),
                                         record.bytes.size());
        if (!frame) break;
        driver.handle(*frame);
        (void)decode_control(*frame);
        (void)decode_rotunit_speed(*frame);
        (void)decode_adc(*frame);
        (void)decode_tilt(*frame);
        if (to_datagram(*frame) != to_datagram(*from_datagram(to_datagram(*frame).data(), 16))) {
          finding("a datagram does not survive a round trip");
        }
        break;
      }
      case 1:
        driver.command_twist(number(record.bytes, 0), number(record.bytes, 1), now);
        break;
      case 2:
        driver.command_wheel_speeds({number(record.bytes, 0), number(record.bytes, 1)}, now);
        break;
      case 3:
        (void)decode_rotunit_speed(driver.command_rotunit(number(record.bytes, 0)));
        break;
      case 4:  // the clock moves on (the driver's 10 ms tick, or a jump)
        now += std::isfinite(number(record.bytes, 0)) ? std::fabs(number(record.bytes, 0)) : 0.01;
        break;
    }
    if (!decode_control(driver.control_frame(now))) finding("a control frame does not decode");
    const auto odometry = driver.odometry();
    if (!std::isfinite(odometry.x) || !std::isfinite(odometry.y) ||
        !(odometry.yaw > -M_PI - 1e-12 && odometry.yaw <= M_PI + 1e-12) ||
        !std::isfinite(odometry.linear) || !std::isfinite(odometry.angular)) {
      finding("the odometry is not finite or its yaw not wrapped");
    }
    for (double range : driver.ranges()) {
      if (!std::isfinite(range)) finding("a range is not finite");
    }
    if (auto gyro = driver.gyro(); gyro && !(std::fabs(gyro->yaw) <= M_PI + 1e-9)) {
      finding("the gyro's yaw is not wrapped");
    }
  }
  return 0;
}
