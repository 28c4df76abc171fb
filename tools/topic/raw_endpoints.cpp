#include "raw_endpoints.h"

#include <chrono>
#include <cstring>

#include "cdr_yaml.h"

namespace macsim::topic {

namespace {

fdds::TypeSupport raw_type(const std::string& type_name) {
  return fdds::TypeSupport(new RawType(type_name, wire_type(type_name)));
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

using eprosima::fastrtps::rtps::SerializedPayload_t;

RawType::RawType(const std::string& type_name, WireTypePtr type) : type_(std::move(type)) {
  setName(type_name.c_str());
  m_isGetKeyDefined = type_ && is_keyed(*type_);
  m_typeSize = 65536;            // a first allocation; samples of any size pass (dynamic memory)
  auto_fill_type_object(false);  // matched by name, as rmw_fastrtps and Cyclone endpoints are
  auto_fill_type_information(false);
}

bool RawType::serialize(void* data, SerializedPayload_t* payload) {
  const auto& bytes = static_cast<RawSample*>(data)->bytes;
  if (bytes.size() < 4) return false;
  payload->reserve(static_cast<uint32_t>(bytes.size()));
  std::memcpy(payload->data, bytes.data(), bytes.size());
  payload->length = static_cast<uint32_t>(bytes.size());
  payload->encapsulation = bytes[1] == 0 ? CDR_BE : CDR_LE;
  return true;
}

bool RawType::deserialize(SerializedPayload_t* payload, void* data) {
  if (payload->length < 4) return false;
  static_cast<RawSample*>(data)->bytes.assign(payload->data, payload->data + payload->length);
  return true;
}

std::function<uint32_t()> RawType::getSerializedSizeProvider(void* data) {
  const auto size = static_cast<uint32_t>(static_cast<RawSample*>(data)->bytes.size());
  return [size] { return size; };
}

void* RawType::createData() { return new RawSample(); }

void RawType::deleteData(void* data) { delete static_cast<RawSample*>(data); }

bool RawType::getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool) {
  if (!m_isGetKeyDefined) return false;
  try {
    const auto key = sample_key(static_cast<RawSample*>(data)->bytes, *type_);
    for (std::size_t i = 0; i < key.size(); ++i) handle->value[i] = key[i];
    return true;
  } catch (const SampleError&) {  // a malformed sample has no key
    return false;
  }
}

RawReader::RawReader(dds::Participant& participant, const std::string& topic,
                     const std::string& type_name, const RawQos& qos, Callback on_sample)
    : participant_(participant), on_sample_(std::move(on_sample)) {
  fdds::DataReaderQos reader_qos;
  participant.subscriber()->get_default_datareader_qos(reader_qos);
  apply(qos, reader_qos);
  reader_ = participant.subscriber()->create_datareader(
      participant.topic(topic, raw_type(type_name)), reader_qos, this);
  if (!reader_) throw dds::DdsError("cannot create a reader on " + topic + " (" + type_name + ")");
  participant.endpoints_changed();
}

RawReader::~RawReader() {
  reader_->set_listener(nullptr);
  participant_.subscriber()->delete_datareader(reader_);
  participant_.endpoints_changed();
}

void RawReader::on_data_available(fdds::DataReader* reader) {
  RawSample sample;
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
  participant.endpoints_changed();
}

RawWriter::~RawWriter() {
  participant_.publisher()->delete_datawriter(writer_);
  participant_.endpoints_changed();
}

bool RawWriter::write(const std::vector<std::uint8_t>& bytes) {
  RawSample sample{bytes};
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
