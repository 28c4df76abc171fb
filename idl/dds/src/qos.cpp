#include "macsim/dds/qos.h"

#include <type_traits>

namespace macsim::dds {

namespace fdds = eprosima::fastdds::dds;

namespace {

struct Policies {
  fdds::ReliabilityQosPolicyKind reliability;
  fdds::DurabilityQosPolicyKind durability;
  int depth;
  bool fast_repair = false;  // heartbeats every 0.1 s: a lost sample is sent again at once
  int writer_depth = 0;      // a writer's history, if deeper than its readers' (0: depth)
};

Policies policies(QosFamily family) {
  switch (family) {
    case QosFamily::Command:
      return {fdds::RELIABLE_RELIABILITY_QOS, fdds::VOLATILE_DURABILITY_QOS, 10, true};
    case QosFamily::Sensor:
      return {fdds::BEST_EFFORT_RELIABILITY_QOS, fdds::VOLATILE_DURABILITY_QOS, 5};
    case QosFamily::State:
      // A writer keeps a second of 100 Hz steps (a third at three times real time): a reader
      // descheduled for less than that under load loses nothing, where the last 10 (33 ms at
      // 300 Hz) were overwritten before it acknowledged them.
      return {fdds::RELIABLE_RELIABILITY_QOS, fdds::VOLATILE_DURABILITY_QOS, 10, false, 100};
    case QosFamily::Latched:
      return {fdds::RELIABLE_RELIABILITY_QOS, fdds::TRANSIENT_LOCAL_DURABILITY_QOS, 1};
  }
  return {fdds::RELIABLE_RELIABILITY_QOS, fdds::VOLATILE_DURABILITY_QOS, 10};
}

template <class Qos>
void apply(const Policies& p, Qos& qos) {
  constexpr bool kWriter = std::is_same_v<Qos, fdds::DataWriterQos>;
  const int depth = kWriter && p.writer_depth > 0 ? p.writer_depth : p.depth;
  qos.reliability().kind = p.reliability;
  qos.durability().kind = p.durability;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = depth;
  // Keyed topics (one instance per object) need more than Fast DDS's default 10 instances.
  constexpr int kMaxInstances = 10000;
  qos.resource_limits().max_instances = kMaxInstances;
  qos.resource_limits().max_samples_per_instance = depth;
  qos.resource_limits().max_samples = kMaxInstances * depth;
  if constexpr (kWriter) {
    if (p.fast_repair) {
      // As deploy/dds/network.xml: a lost command, reply or progress is sent again within
      // ~0.1 s, not after Fast DDS's default 3 s heartbeat (longer than a client waits on a
      // silent server before it calls it gone).
      auto& times = qos.reliable_writer_qos().times;
      times.initialHeartbeatDelay = {0, 10000000};
      times.heartbeatPeriod = {0, 100000000};
      times.nackResponseDelay = {0, 5000000};
    }
  }
}

}  // namespace

const char* profile_name(QosFamily family) {
  switch (family) {
    case QosFamily::Command:
      return "macsim_command";
    case QosFamily::Sensor:
      return "macsim_sensor";
    case QosFamily::State:
      return "macsim_state";
    case QosFamily::Latched:
      return "macsim_latched";
  }
  return "";
}

fdds::DataWriterQos writer_qos(QosFamily family, fdds::Publisher* publisher) {
  fdds::DataWriterQos qos;
  if (publisher->get_datawriter_qos_from_profile(profile_name(family), qos) ==
      ReturnCode_t::RETCODE_OK) {
    return qos;  // the loaded XML profiles decide
  }
  qos = publisher->get_default_datawriter_qos();
  apply(policies(family), qos);
  return qos;
}

fdds::DataReaderQos reader_qos(QosFamily family, fdds::Subscriber* subscriber) {
  fdds::DataReaderQos qos;
  if (subscriber->get_datareader_qos_from_profile(profile_name(family), qos) ==
      ReturnCode_t::RETCODE_OK) {
    return qos;
  }
  qos = subscriber->get_default_datareader_qos();
  apply(policies(family), qos);
  return qos;
}

}  // namespace macsim::dds
