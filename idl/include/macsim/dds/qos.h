// QoS families of MACSim-DDS topics: one policy set per kind of data.
#pragma once

#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

namespace macsim::dds {

/// What kind of data a topic carries, which decides its QoS.
enum class QosFamily {
  Command,  ///< controller -> robot: reliable, volatile, keep last 10
  Sensor,   ///< high-rate robot data and the clock: best effort, volatile, keep last 5
  Latched,  ///< state a late joiner must see: reliable, transient local, keep last 1
};

/// Writer QoS of a family, starting from the publisher's (XML-configurable) default.
eprosima::fastdds::dds::DataWriterQos writer_qos(QosFamily family,
                                                 eprosima::fastdds::dds::Publisher* publisher);
/// Reader QoS of a family, starting from the subscriber's (XML-configurable) default.
eprosima::fastdds::dds::DataReaderQos reader_qos(QosFamily family,
                                                 eprosima::fastdds::dds::Subscriber* subscriber);

}  // namespace macsim::dds
