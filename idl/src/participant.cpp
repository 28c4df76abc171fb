#include "macsim/dds/participant.h"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

namespace macsim::dds {

Participant::Participant(const ParticipantOptions& options) : domain_(options.domain) {
  if (options.domain < 0 || options.domain > kMaxDomainId) {
    throw DdsError("domain id " + std::to_string(options.domain) + " is outside 0.." +
                   std::to_string(kMaxDomainId));
  }
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  // Profiles load lazily: load them before taking the default QoS, or the XML is ignored.
  if (!options.profile_file.empty() &&
      factory->load_XML_profiles_file(options.profile_file) != ReturnCode_t::RETCODE_OK) {
    throw DdsError("cannot load the Fast DDS profile file '" + options.profile_file + "'");
  }
  factory->load_profiles();
  fdds::DomainParticipantQos qos;
  factory->get_default_participant_qos(qos);
  qos.name(options.name);
  // StatusMask::none(): discovery callbacks still come, data callbacks stay with the readers.
  participant_ =
      factory->create_participant(options.domain, qos, options.listener, fdds::StatusMask::none());
  if (!participant_)
    throw DdsError("cannot create a participant on domain " + std::to_string(options.domain));
  publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  if (!publisher_ || !subscriber_) throw DdsError("cannot create a publisher or subscriber");
}

Participant::~Participant() {
  if (!participant_) return;
  participant_->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
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
