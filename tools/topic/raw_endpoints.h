// Readers and writers of serialized samples on any topic of the IDL's types: what echo, hz, bw,
// record, pub and play use, so a sample is never decoded unless it is printed.
#pragma once

#include <atomic>
#include <cstdint>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <functional>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"
#include "wire_type.h"

namespace macsim::topic {

namespace fdds = eprosima::fastdds::dds;

/// One sample as it travels: the 4-byte encapsulation header, then the CDR body.
struct RawSample {
  std::vector<std::uint8_t> bytes;
};

/// Type support for RawSample under any type name: samples pass through unchanged. With the
/// IDL's description of that type, keyed topics work too (the key is read from the sample).
class RawType : public fdds::TopicDataType {
 public:
  /// `type` may be null (a type the IDL does not have): the topic is taken as unkeyed.
  RawType(const std::string& type_name, WireTypePtr type);

  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override;
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override;
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override;
  void* createData() override;
  void deleteData(void* data) override;
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle,
              bool force_md5) override;

 private:
  WireTypePtr type_;
};

/// QoS of a tool's reader or writer.
struct RawQos {
  bool reliable = false;
  bool transient_local = false;
  int depth = 100;  ///< keep last; 0 keeps all (a recorder: nothing dropped while it keeps up)
};

/// A sample as it arrived.
struct ReceivedSample {
  std::vector<std::uint8_t> bytes;  ///< encapsulation header + CDR
  std::int64_t received_ns = 0;     ///< system clock, ns since the epoch
  std::int64_t source_ns = 0;       ///< the writer's source timestamp
};

/// Reads serialized samples of `type_name` on `topic`; the callback runs on Fast DDS's thread.
class RawReader : private fdds::DataReaderListener {
 public:
  using Callback = std::function<void(ReceivedSample&&)>;
  RawReader(dds::Participant& participant, const std::string& topic, const std::string& type_name,
            const RawQos& qos, Callback on_sample);
  ~RawReader() override;
  RawReader(const RawReader&) = delete;
  RawReader& operator=(const RawReader&) = delete;

  /// Writers currently matched.
  int matched() const { return matched_.load(); }
  /// Samples the middleware reported lost (best effort gaps) or rejected.
  std::uint64_t lost() const { return lost_.load(); }

 private:
  void on_data_available(fdds::DataReader* reader) override;
  void on_subscription_matched(fdds::DataReader*,
                               const fdds::SubscriptionMatchedStatus& status) override;
  void on_sample_lost(fdds::DataReader*, const fdds::SampleLostStatus& status) override;

  dds::Participant& participant_;
  Callback on_sample_;
  std::atomic<int> matched_{0};
  std::atomic<std::uint64_t> lost_{0};
  fdds::DataReader* reader_ = nullptr;
};

/// Writes serialized samples of `type_name` on `topic`.
class RawWriter {
 public:
  RawWriter(dds::Participant& participant, const std::string& topic, const std::string& type_name,
            const RawQos& qos);
  ~RawWriter();
  RawWriter(const RawWriter&) = delete;
  RawWriter& operator=(const RawWriter&) = delete;

  /// Publishes one sample (header + CDR); false if Fast DDS refused it.
  bool write(const std::vector<std::uint8_t>& bytes);
  /// Readers currently matched.
  int matched() const;
  /// Waits until matched reliable readers acknowledged everything written.
  bool wait_acknowledged(std::chrono::milliseconds timeout);

 private:
  dds::Participant& participant_;
  fdds::DataWriter* writer_ = nullptr;
};

}  // namespace macsim::topic
