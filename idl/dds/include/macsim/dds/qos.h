// QoS families of MACSim-DDS topics: one policy set per kind of data.
#pragma once

#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

namespace macsim::dds {

/// What kind of data a topic carries, which decides its QoS.
enum class QosFamily {
  Command,  ///< controller -> robot: reliable, volatile, keep last 10, acknowledged within
            ///< ~0.2 ms, no data sharing (a killed peer's reader would hold the samples)
  Sensor,   ///< images, scans, clouds, ranges: best effort, volatile, keep last 5 (SensorDataQoS)
  State,    ///< odometry, IMU, joint and crane states, clock: reliable, volatile, keep last 10
            ///< (writers keep 100; a default ROS 2 subscription matches; best effort too)
  Latched,  ///< state a late joiner must see: reliable, transient local, keep last 1
  Request,  ///< requests and replies of a service: command's, with a heartbeat of 0.1 s
  LockstepSensor,  ///< sensor data of a lock-step simulator: sensor's, but reliable (a sample
                   ///< sent once, at a request's end, is repaired when lost; SensorDataQoS
                   ///< readers still match); a reader of it reads state topics reliably too
};

/// The family of sensor data: LockstepSensor between a lock-step simulator and its clients,
/// Sensor otherwise.
constexpr QosFamily sensor_family(bool lockstep) {
  return lockstep ? QosFamily::LockstepSensor : QosFamily::Sensor;
}

/// The XML profile name of a family's data writers and readers ("macsim_command", ...).
const char* profile_name(QosFamily family);
/// Loads the built-in family profiles (deploy/dds/qos.xml) the loaded XML does not define yet;
/// Participant calls it after loading the deployment's profile, which so overrides a family.
void load_builtin_qos_families();
/// Writer QoS of a family: the loaded XML profile of that name (DdsError if there is none).
eprosima::fastdds::dds::DataWriterQos writer_qos(QosFamily family,
                                                 eprosima::fastdds::dds::Publisher* publisher);
/// Reader QoS of a family, likewise.
eprosima::fastdds::dds::DataReaderQos reader_qos(QosFamily family,
                                                 eprosima::fastdds::dds::Subscriber* subscriber);

}  // namespace macsim::dds
