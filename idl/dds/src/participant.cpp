#include "macsim/dds/participant.h"

#include <fastrtps/xmlparser/XMLProfileManager.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>

#include "macsim/dds/log.h"
#include "macsim/msg/rmw_dds_commonPubSubTypes.h"

namespace macsim::dds {

namespace {

namespace rdc = rmw_dds_common::msg::dds_;

/// A ROS 2 node name from a participant name: letters, digits and '_', not starting with a digit.
std::string node_name_of(const std::string& name) {
  std::string node;
  for (char c : name) node += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (node.empty() || std::isdigit(static_cast<unsigned char>(node[0]))) node = "_" + node;
  return node;
}

/// Fast DDS 2.9 loads XML profiles into process-wide tables without a lock (fixed upstream after
/// 2.9): participants made at once from several threads would load them together, log "Error
/// adding profile" and now and then crash. One participant of this process loads at a time.
std::mutex& profile_loading() {
  static std::mutex mutex;
  return mutex;
}

/// Fast DDS 2.9 delivers discovery data to the other participants of the same process by
/// pointer; deleting an endpoint right after another participant of the process went away could
/// follow a pointer to that participant's deleted discovery reader (a segfault under load seen
/// here in two-participant tests; fixed upstream by Fast DDS PR #5034, 2.10.5 and 2.14, not in
/// Debian 12's 2.9). Discovery data goes through the transport (shared memory) instead; user
/// data keeps the in-process shortcut. An XML profile that turns the shortcut off stays obeyed.
void discovery_through_the_transport() {
  namespace xml = eprosima::fastrtps::xmlparser;
  auto settings = xml::XMLProfileManager::library_settings();
  if (settings.intraprocess_delivery == eprosima::fastrtps::INTRAPROCESS_FULL) {
    settings.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_USER_DATA_ONLY;
    xml::XMLProfileManager::library_settings(settings);
  }
}

/// `file`, or FASTRTPS_DEFAULT_PROFILES_FILE if that names the same file: Fast DDS knows a file
/// it has loaded by the name it was given, and would load it again under another name, logging
/// an error for every profile already there.
std::string same_file_as_default(const std::string& file) {
  const char* default_file = std::getenv("FASTRTPS_DEFAULT_PROFILES_FILE");
  std::error_code error;
  if (default_file && std::filesystem::equivalent(file, default_file, error)) return default_file;
  return file;
}

/// The lowest participant id whose two unicast shared-memory ports (Fast DDS's default port
/// mapping: 7400 + 250 * domain + 10 + 2 * id, and the next) have no segment in /dev/shm yet,
/// or -1 (Fast DDS then chooses). Fast DDS 2.9 itself takes the lowest id whose port no live
/// process holds, and so takes a killed participant's: it removes that "zombie" port's segment
/// and makes a new one, while the participants that wrote to the killed one keep writing into
/// the removed segment, and the new process never hears them (eProsima/Fast-DDS#5053, PR
/// #4728). A simulator killed and started again (macsim --resume) met this: its controller's
/// step requests never reached it.
/// The participant ids this process's participants hold, by participant (Fast DDS refuses an id
/// one of them has, whatever its domain). Under profile_loading().
std::map<const fdds::DomainParticipant*, int>& ids_held() {
  static std::map<const fdds::DomainParticipant*, int> held;
  return held;
}

int fresh_participant_id(int domain) {
  std::error_code error;
  if (!std::filesystem::is_directory("/dev/shm", error)) return -1;
  for (int id = 0; id < 120; ++id) {
    const auto& held = ids_held();
    if (std::any_of(held.begin(), held.end(), [&](const auto& h) { return h.second == id; }))
      continue;
    const int port = 7400 + 250 * domain + 10 + 2 * id;
    if (port + 1 > 65535) break;
    const auto taken = [&](int p) {
      std::error_code e;
      return std::filesystem::exists("/dev/shm/fastrtps_port" + std::to_string(p), e);
    };
    if (!taken(port) && !taken(port + 1)) return id;
  }
  return -1;
}

rdc::Gid_ gid_of(const eprosima::fastrtps::rtps::GUID_t& guid) {
  rdc::Gid_ gid;
  std::copy(guid.guidPrefix.value, guid.guidPrefix.value + 12, gid.data().begin());
  std::copy(guid.entityId.value, guid.entityId.value + 4, gid.data().begin() + 12);
  return gid;
}

}  // namespace

SampleId sample_id(const eprosima::fastrtps::rtps::SampleIdentity& identity) {
  SampleId id;
  const auto& guid = identity.writer_guid();
  std::copy(guid.guidPrefix.value, guid.guidPrefix.value + 12, id.writer.begin());
  std::copy(guid.entityId.value, guid.entityId.value + 4, id.writer.begin() + 12);
  id.sequence = identity.sequence_number().to64long();
  return id;
}

Participant::Participant(const ParticipantOptions& options) : domain_(options.domain) {
  if (options.domain < 0 || options.domain > kMaxDomainId) {
    throw DdsError("domain id " + std::to_string(options.domain) + " is outside 0.." +
                   std::to_string(kMaxDomainId));
  }
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  std::unique_lock<std::mutex> loading(profile_loading());  // until the participant exists
  // Profiles load lazily: load them before taking the default QoS, or the XML is ignored.
  if (!options.profile_file.empty() && factory->load_XML_profiles_file(same_file_as_default(
                                           options.profile_file)) != ReturnCode_t::RETCODE_OK) {
    throw DdsError("cannot load the Fast DDS profile file '" + options.profile_file + "'");
  }
  factory->load_profiles();
  load_builtin_qos_families();  // after the deployment's profile, whose families win
  discovery_through_the_transport();
  fdds::DomainParticipantQos qos;
  factory->get_default_participant_qos(qos);
  qos.name(options.name);
  if (options.ros_node) {
    // What a ROS 2 Jazzy participant carries: its security enclave, the root one.
    const std::string enclave = "enclave=/;";
    qos.user_data().data_vec(
        std::vector<eprosima::fastrtps::rtps::octet>(enclave.begin(), enclave.end()));
  }
  // StatusMask::none(): discovery callbacks still come, data callbacks stay with the readers.
  // Ports no killed participant left behind (fresh_participant_id()); Fast DDS's own choice if
  // that id cannot be had (another participant of this process took it without shared memory).
  if (qos.wire_protocol().participant_id < 0)
    qos.wire_protocol().participant_id = fresh_participant_id(options.domain);
  participant_ =
      factory->create_participant(options.domain, qos, options.listener, fdds::StatusMask::none());
  if (!participant_ && qos.wire_protocol().participant_id >= 0) {
    qos.wire_protocol().participant_id = -1;
    participant_ = factory->create_participant(options.domain, qos, options.listener,
                                               fdds::StatusMask::none());
  }
  if (participant_ && qos.wire_protocol().participant_id >= 0)
    ids_held()[participant_] = qos.wire_protocol().participant_id;
  loading.unlock();
  if (!participant_)
    throw DdsError("cannot create a participant on domain " + std::to_string(options.domain));
  publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  if (!publisher_ || !subscriber_) throw DdsError("cannot create a publisher or subscriber");
  if (options.ros_node) {
    node_name_ = node_name_of(options.name);
    graph_writer_ = publisher_->create_datawriter(
        topic<rdc::ParticipantEntitiesInfo_PubSubType>("ros_discovery_info"),
        writer_qos(QosFamily::Latched, publisher_));
    if (graph_writer_) {
      endpoints_changed();
    } else {  // e.g. refused by DDS Security permissions: the participant works on unannounced
      log::warn("{}: not in the ROS 2 graph (cannot create the ros_discovery_info writer)",
                options.name);
    }
  }
}

void Participant::endpoints_changed() {
  if (!graph_writer_) return;
  std::lock_guard<std::mutex> lock(graph_mutex_);
  std::vector<fdds::DataWriter*> writers;
  std::vector<fdds::DataReader*> readers;
  publisher_->get_datawriters(writers);
  subscriber_->get_datareaders(readers);
  rdc::NodeEntitiesInfo_ node;
  node.node_namespace("/");
  node.node_name(node_name_);
  for (fdds::DataWriter* w : writers) {
    if (w != graph_writer_) node.writer_gid_seq().push_back(gid_of(w->guid()));
  }
  for (fdds::DataReader* r : readers) node.reader_gid_seq().push_back(gid_of(r->guid()));
  rdc::ParticipantEntitiesInfo_ info;
  info.gid(gid_of(participant_->guid()));
  info.node_entities_info_seq().push_back(std::move(node));
  graph_writer_->write(&info);
}

Participant::~Participant() {
  if (!participant_) return;
  participant_->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  std::lock_guard<std::mutex> loading(profile_loading());
  ids_held().erase(participant_);
}

fdds::Topic* Participant::make_topic(const std::string& name, fdds::TypeSupport type) {
  if (participant_->find_type(type.get_type_name()) == nullptr &&
      type.register_type(participant_) != ReturnCode_t::RETCODE_OK) {
    throw DdsError("cannot register type " + type.get_type_name());
  }
  fdds::Topic* topic =
      participant_->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  if (!topic) throw DdsError("cannot create topic " + name + " of type " + type.get_type_name());
  topics_.emplace(name, topic);
  return topic;
}

}  // namespace macsim::dds
