// A Fast DDS domain participant set up the MACSim-DDS way, with typed writers and readers.
#pragma once

#include <fastdds/rtps/common/WriteParams.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include "macsim/dds/qos.h"

namespace macsim::dds {

namespace fdds = eprosima::fastdds::dds;

/// Raised when a DDS entity cannot be created; the message says which and why.
struct DdsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Who wrote a sample and its place among what that writer wrote (DDS's sample identity): a
/// writer numbers its samples 1, 2, 3, ... in the order it writes them.
struct SampleId {
  std::array<uint8_t, 16> writer{};  ///< the writer's GUID
  uint64_t sequence = 0;             ///< the sample's sequence number
};

/// The SampleId of Fast DDS's sample identity.
SampleId sample_id(const eprosima::fastrtps::rtps::SampleIdentity& identity);

/// How to join DDS: domain id, optional Fast DDS XML profile file, participant name.
struct ParticipantOptions {
  int domain = 0;
  std::string profile_file;  ///< empty: FASTRTPS_DEFAULT_PROFILES_FILE or Fast DDS defaults
  std::string name = "macsim";
  /// Hears discovery from the start (participants, writers, readers); not owned.
  fdds::DomainParticipantListener* listener = nullptr;
  /// Appear in the ROS 2 graph as the node /<name> (ros_discovery_info, enclave "/"), so that
  /// `ros2 node list` and `ros2 node info` show the participant and its endpoints.
  bool ros_node = true;
};

/// Highest domain id Fast DDS's default port mapping allows.
inline constexpr int kMaxDomainId = 232;

/// A generated type whose deserialize answers a malformed sample with false, so that Fast DDS
/// drops it, instead of letting Fast CDR's exception end the process (one bad packet on the
/// network must not kill a participant). Every topic of a Participant uses it.
template <class PubSubType>
class CheckedType : public PubSubType {
 public:
  CheckedType() {
    // Matched by type name, as rmw_fastrtps and Cyclone endpoints are: no type object goes out
    // in discovery (Fast DDS 2.9 crashes building some it receives, e.g. those of sequences).
    this->auto_fill_type_object(false);
    this->auto_fill_type_information(false);
  }
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    try {
      return PubSubType::deserialize(payload, data);
    } catch (...) {  // eprosima::fastcdr::exception::Exception: bad encapsulation, union, length
      return false;
    }
  }
};

/// Owns a DomainParticipant (from the default participant QoS after the XML profiles are
/// loaded), one publisher, one subscriber and the topics; deletes them all on destruction.
class Participant {
 public:
  explicit Participant(const ParticipantOptions& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  /// The topic of that name, registering the type and creating the topic on first use.
  template <class PubSubType>
  fdds::Topic* topic(const std::string& name) {
    auto found = topics_.find(name);
    if (found != topics_.end()) return found->second;
    fdds::TypeSupport type(new CheckedType<PubSubType>());
    return make_topic(name, type);
  }

  /// The topic of that name with a type support the caller built (tools handling any type).
  fdds::Topic* topic(const std::string& name, fdds::TypeSupport type) {
    auto found = topics_.find(name);
    if (found != topics_.end()) return found->second;
    return make_topic(name, type);
  }

  /// Announces the current readers and writers to the ROS 2 graph (ros_discovery_info); every
  /// entity that creates or deletes a reader or writer calls it.
  void endpoints_changed();
  /// The ROS 2 node name this participant announces ("" if it announces none).
  const std::string& ros_node_name() const { return node_name_; }

  fdds::DomainParticipant* get() const { return participant_; }
  fdds::Publisher* publisher() const { return publisher_; }
  fdds::Subscriber* subscriber() const { return subscriber_; }
  int domain() const { return domain_; }

 private:
  fdds::Topic* make_topic(const std::string& name, fdds::TypeSupport type);

  int domain_;
  std::string node_name_;
  std::mutex graph_mutex_;                    // one ros_discovery_info sample at a time
  fdds::DataWriter* graph_writer_ = nullptr;  // ros_discovery_info, if a ROS node
  fdds::DomainParticipant* participant_ = nullptr;
  fdds::Publisher* publisher_ = nullptr;
  fdds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, fdds::Topic*> topics_;
};

/// A typed data writer on one topic, with the QoS of its family.
template <class PubSubType>
class Writer {
 public:
  using Data = typename PubSubType::type;

  Writer(Participant& participant, const std::string& topic_name, QosFamily family)
      : participant_(participant), topic_name_(topic_name) {
    writer_ = participant.publisher()->create_datawriter(
        participant.topic<PubSubType>(topic_name), writer_qos(family, participant.publisher()));
    if (!writer_) throw DdsError("cannot create a writer on " + topic_name);
    participant.endpoints_changed();
  }
  ~Writer() {
    participant_.publisher()->delete_datawriter(writer_);
    participant_.endpoints_changed();
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// Publishes one sample; false if Fast DDS refused it.
  bool write(const Data& sample) { return writer_->write(const_cast<Data*>(&sample)); }
  /// Publishes one sample and gives its identity (`sent`, when written).
  bool write(const Data& sample, SampleId& sent) {
    eprosima::fastrtps::rtps::WriteParams params;
    if (!writer_->write(const_cast<Data*>(&sample), params)) return false;
    sent = sample_id(params.sample_identity());
    return true;
  }
  /// Disposes the instance of a keyed topic that `sample`'s key names.
  bool dispose(const Data& sample) {
    return writer_->dispose(const_cast<Data*>(&sample), fdds::HANDLE_NIL) ==
           ReturnCode_t::RETCODE_OK;
  }
  /// Number of readers currently matched.
  int matched() const {
    fdds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return status.current_count;
  }
  /// Readers matched so far, those gone included: a reader new since shows as a change.
  int matched_ever() const {
    fdds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return status.total_count;
  }
  const std::string& topic_name() const { return topic_name_; }
  /// Waits until every matched reliable reader acknowledged what was written (lock-step:
  /// the command is in the simulator's queue before the next step request).
  bool wait_acknowledged(std::chrono::milliseconds timeout) {
    eprosima::fastrtps::Duration_t max_wait(
        static_cast<int32_t>(timeout.count() / 1000),
        static_cast<uint32_t>((timeout.count() % 1000) * 1000000));
    return writer_->wait_for_acknowledgments(max_wait) == ReturnCode_t::RETCODE_OK;
  }

 private:
  Participant& participant_;
  std::string topic_name_;
  fdds::DataWriter* writer_ = nullptr;
};

/// A typed data reader that hands every valid sample to a callback on Fast DDS's thread.
/// The callback must be short and thread-safe: copy or enqueue, never act on shared state.
template <class PubSubType>
class Reader : private fdds::DataReaderListener {
 public:
  using Data = typename PubSubType::type;
  using Callback = std::function<void(const Data&)>;
  /// A callback that also learns who wrote the sample and its place among that writer's.
  using SentCallback = std::function<void(const Data&, const SampleId&)>;

  /// `on_gone`, if given, hears of instances disposed or left without writers (keyed topics):
  /// it gets the instance's last sample.
  Reader(Participant& participant, const std::string& topic_name, QosFamily family,
         Callback on_sample, Callback on_gone = {})
      : Reader(participant, topic_name, family,
               SentCallback([on_sample = std::move(on_sample)](const Data& d, const SampleId&) {
                 on_sample(d);
               }),
               std::move(on_gone)) {}
  /// The same, each sample handed over with its writer and sequence number.
  Reader(Participant& participant, const std::string& topic_name, QosFamily family,
         SentCallback on_sample, Callback on_gone = {})
      : participant_(participant), on_sample_(std::move(on_sample)), on_gone_(std::move(on_gone)) {
    reader_ = participant.subscriber()->create_datareader(
        participant.topic<PubSubType>(topic_name), reader_qos(family, participant.subscriber()),
        this);
    if (!reader_) throw DdsError("cannot create a reader on " + topic_name);
    participant.endpoints_changed();
  }
  ~Reader() override {
    reader_->set_listener(nullptr);
    participant_.subscriber()->delete_datareader(reader_);
    participant_.endpoints_changed();
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  /// Number of writers currently matched.
  int matched() const { return matched_.load(); }
  /// Writers matched so far, those gone included: a writer new since shows as a change.
  int matched_ever() const { return matched_ever_.load(); }
  /// Hands every sample already received to the callback now, on the caller's thread (the
  /// simulation's drain point: whatever a writer saw acknowledged is taken in this step).
  /// Samples reach the callback in the order they were received, whichever thread takes them.
  void poll() { drain(reader_, true); }

 private:
  void on_data_available(fdds::DataReader* reader) override {
    // Never block here: Fast DDS may hold its own lock while it calls us.
    drain(reader, false);
  }
  /// Takes until the reader is empty, one thread at a time so samples stay in order. A thread
  /// that finds another taking (and may not wait) leaves a flag; the taker looks again.
  void drain(fdds::DataReader* reader, bool wait) {
    while (true) {
      std::unique_lock<std::mutex> lock(take_mutex_, std::defer_lock);
      if (wait) {
        lock.lock();
      } else if (!lock.try_lock()) {
        deferred_.store(true);
        if (!lock.try_lock()) return;  // the taker sees the flag after it lets go
      }
      do {
        take_all(reader);
      } while (deferred_.exchange(false));
      lock.unlock();
      if (!deferred_.load()) return;  // someone came while we let go: go again
    }
  }
  void take_all(fdds::DataReader* reader) {
    Data sample;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) {
        if (on_gone_) last_[info.instance_handle] = sample;
        on_sample_(sample, sample_id(info.sample_identity));
      } else if (on_gone_ && info.instance_state != fdds::ALIVE_INSTANCE_STATE) {
        // Fast DDS 2.9 cannot give the key of a handle: remember each instance's last sample.
        auto last = last_.find(info.instance_handle);
        if (last != last_.end()) {
          on_gone_(last->second);
          last_.erase(last);
        }
      }
    }
  }
  void on_subscription_matched(fdds::DataReader*,
                               const fdds::SubscriptionMatchedStatus& status) override {
    matched_.store(status.current_count);
    matched_ever_.store(status.total_count);
  }

  Participant& participant_;
  SentCallback on_sample_;
  Callback on_gone_;
  std::mutex take_mutex_;  // one thread takes at a time, so samples stay in order
  std::atomic<bool> deferred_{false};
  std::map<fdds::InstanceHandle_t, Data> last_;  // only with on_gone_
  std::atomic<int> matched_{0};
  std::atomic<int> matched_ever_{0};
  fdds::DataReader* reader_ = nullptr;
};

}  // namespace macsim::dds
