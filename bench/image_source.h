// The benchmarks' bare image source: 640x480 bgr8 images at 30 Hz, stamped with the sending time
// on the steady clock (CLOCK_MONOTONIC, the same in every process of the machine).
#pragma once

#include <chrono>
#include <string>
#include <thread>

#include "macsim/dds/convert.h"
#include "macsim/dds/participant.h"
#include "macsim/msg/sensor_msgsPubSubTypes.h"

namespace macsim::bench {

/// Publishes on `topic` until the process ends.
[[noreturn]] inline void publish_images(dds::Participant& participant, const std::string& topic) {
  using Clock = std::chrono::steady_clock;
  dds::Writer<sensor_msgs::msg::dds_::Image_PubSubType> writer(participant, topic,
                                                               dds::QosFamily::Sensor);
  sensor_msgs::msg::dds_::Image_ image;
  image.height(480);
  image.width(640);
  image.encoding("bgr8");
  image.step(640 * 3);
  image.data().assign(640 * 480 * 3, 128);
  auto next = Clock::now();
  while (true) {
    next += std::chrono::microseconds(33333);
    std::this_thread::sleep_until(next);
    image.header().stamp(
        dds::to_time(std::chrono::duration<double>(Clock::now().time_since_epoch()).count()));
    writer.write(image);
  }
}

}  // namespace macsim::bench
