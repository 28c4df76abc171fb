#include "raw_endpoints.h"

#include <chrono>

#include "macsim/dds/dynamic_types.h"

namespace macsim::topic {

namespace {

fdds::TypeSupport raw_type(const std::string& type_name) {
  return fdds::TypeSupport(new dds::RawType(type_name, dds::idl_dynamic_type(type_name)));
}

template <class Qos>
void apply(const RawQos& qos, Qos& out) {
  out.reliability().kind =
      qos.reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
  out.durability().kind =
      qos.transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  if (qos.depth > 0) {
    out.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    out.history().depth = qos.depth;
  } else {
    out.history().kind = fdds::KEEP_ALL_HISTORY_QOS;
  }
  // many instances (the world's objects; a reader out of instances stalls a reliable keyed
  // writer), samples of any size (camera images), allocated as they come
  out.resource_limits().max_instances = 10000;
  out.resource_limits().max_samples_per_instance = qos.depth > 0 ? qos.depth : 1000;
  out.resource_limits().max_samples = 10000 * out.resource_limits().max_samples_per_instance;
  out.endpoint().history_memory_policy = eprosima::fastrtps::rtps::DYNAMIC_REUSABLE_MEMORY_MODE;
}

std::int64_t nanoseconds(const eprosima::fastrtps::rtps::Time_t& t) {
  return static_cast<std::int64_t>(t.seconds()) * 1000000000LL + t.nanosec();
}

}  // namespace

RawReader::RawReader(dds::Participant& participant, const std::string& topic,
                     const std::string& type_name, const RawQos& qos, Callback on_sample)
    : participant_(participant), on_sample_(std::move(on_sample)) {
  fdds::DataReaderQos reader_qos;
  participant.subscriber()->get_default_datareader_qos(reader_qos);
  apply(qos, reader_qos);
  reader_ = participant.subscriber()->create_datareader(
      participant.topic(topic, raw_type(type_name)), reader_qos, this);
  if (!reader_) throw dds::DdsError("cannot create a reader on " + topic + " (" + type_name + ")");
}

RawReader::~RawReader() {
  reader_->set_listener(nullptr);
  participant_.subscriber()->delete_datareader(reader_);
}

void RawReader::on_data_available(fdds::DataReader* reader) {
  dds::RawSample sample;
  fdds::SampleInfo info;
  while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
    if (!info.valid_data) continue;
    ReceivedSample received;
    received.bytes = std::move(sample.bytes);
    received.received_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               std::chrono::system_clock::now().time_since_epoch())
                               .count();
    received.source_ns = nanoseconds(info.source_timestamp);
    on_sample_(std::move(received));
  }
}

void RawReader::on_subscription_matched(fdds::DataReader*,
                                        const fdds::SubscriptionMatchedStatus& status) {
  matched_.store(status.current_count);
}

void RawReader::on_sample_lost(fdds::DataReader*, const fdds::SampleLostStatus& status) {
  lost_.store(static_cast<std::uint64_t>(status.total_count));
}

RawWriter::RawWriter(dds::Participant& participant, const std::string& topic,
                     const std::string& type_name, const RawQos& qos)
    : participant_(participant) {
  fdds::DataWriterQos writer_qos;
  participant.publisher()->get_default_datawriter_qos(writer_qos);
  apply(qos, writer_qos);
  writer_ = participant.publisher()->create_datawriter(
      participant.topic(topic, raw_type(type_name)), writer_qos);
  if (!writer_) throw dds::DdsError("cannot create a writer on " + topic + " (" + type_name + ")");
}

RawWriter::~RawWriter() { participant_.publisher()->delete_datawriter(writer_); }

bool RawWriter::write(const std::vector<std::uint8_t>& bytes) {
  dds::RawSample sample{bytes};
  return writer_->write(&sample);
}

int RawWriter::matched() const {
  fdds::PublicationMatchedStatus status;
  writer_->get_publication_matched_status(status);
  return status.current_count;
}

bool RawWriter::wait_acknowledged(std::chrono::milliseconds timeout) {
  eprosima::fastrtps::Duration_t max_wait(
      static_cast<int32_t>(timeout.count() / 1000),
      static_cast<uint32_t>((timeout.count() % 1000) * 1000000));
  return writer_->wait_for_acknowledgments(max_wait) == ReturnCode_t::RETCODE_OK;
}

}  // namespace macsim::topic
