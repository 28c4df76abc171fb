// A writer whose samples DDS delivers late on purpose: its own participant sends at most one
// small sample per `period` (a Fast DDS flow controller), so a sample written right after
// another leaves about one period later, while other writers' samples go at once. Across
// processes only (within one, Fast DDS hands samples over without a transport).
#pragma once

#include <chrono>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/rtps/flowcontrol/FlowControllerDescriptor.hpp>
#include <memory>
#include <stdexcept>
#include <string>

#include "macsim/dds/participant.h"

namespace macsim::test {

template <class PubSubType>
class LateWriter {
 public:
  using Data = typename PubSubType::type;

  LateWriter(int domain, const std::string& topic_name, std::chrono::milliseconds period) {
    namespace fdds = eprosima::fastdds::dds;
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    factory->load_profiles();
    fdds::DomainParticipantQos qos;
    factory->get_default_participant_qos(qos);  // the shipped profile's transports
    qos.name("late_writer");
    auto slow = std::make_shared<eprosima::fastdds::rtps::FlowControllerDescriptor>();
    slow->name = kController;
    slow->max_bytes_per_period = 100;  // one small sample with its headers
    slow->period_ms = static_cast<uint64_t>(period.count());
    qos.flow_controllers().push_back(slow);
    participant_ = factory->create_participant(domain, qos);
    if (!participant_) throw std::runtime_error("cannot create the late writer's participant");
    fdds::TypeSupport type(new dds::CheckedType<PubSubType>());
    type.register_type(participant_);
    auto* topic =
        participant_->create_topic(topic_name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    auto* publisher = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    fdds::DataWriterQos writer_qos = dds::writer_qos(dds::QosFamily::Command, publisher);
    writer_qos.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
    writer_qos.publish_mode().flow_controller_name = kController;
    // A type of fixed size would otherwise go through shared memory without a transport, past
    // the flow controller.
    writer_qos.data_sharing().off();
    writer_ = publisher->create_datawriter(topic, writer_qos);
    if (!writer_) throw std::runtime_error("cannot create the late writer on " + topic_name);
  }
  ~LateWriter() {
    participant_->delete_contained_entities();
    eprosima::fastdds::dds::DomainParticipantFactory::get_instance()->delete_participant(
        participant_);
  }
  LateWriter(const LateWriter&) = delete;
  LateWriter& operator=(const LateWriter&) = delete;

  /// Writes one sample; its identity (writer and sequence number).
  dds::SampleId write(const Data& sample) {
    eprosima::fastrtps::rtps::WriteParams params;
    if (!writer_->write(const_cast<Data*>(&sample), params))
      throw std::runtime_error("the late writer could not write");
    return dds::sample_id(params.sample_identity());
  }
  /// True once every matched reader acknowledged what was written.
  bool delivered(std::chrono::milliseconds timeout) {
    eprosima::fastrtps::Duration_t wait(static_cast<int32_t>(timeout.count() / 1000),
                                        static_cast<uint32_t>(timeout.count() % 1000) * 1000000);
    return writer_->wait_for_acknowledgments(wait) == ReturnCode_t::RETCODE_OK;
  }
  /// Number of readers matched.
  int matched() const {
    eprosima::fastdds::dds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return status.current_count;
  }

 private:
  static constexpr const char* kController = "late_writer_flow";
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace macsim::test
