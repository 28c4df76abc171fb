// What discovery tells about a domain: every remote participant, writer and reader, grouped by
// topic (the builtin discovery topics, no type knowledge needed).
#pragma once

#include <chrono>
#include <condition_variable>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace macsim::topic {

namespace fdds = eprosima::fastdds::dds;

/// One writer or reader seen through discovery.
struct Endpoint {
  std::string guid;         ///< GUID as Fast DDS prints it
  std::string participant;  ///< the participant's name ("macsim", "helloKurt", ...)
  std::string type;         ///< DDS type name
  bool writer = false;
  bool reliable = false;
  bool transient_local = false;
  bool keyed = false;
};

/// A topic and the endpoints on it.
struct TopicSummary {
  std::string name;                ///< DDS topic name ("rt/kurt/odom")
  std::vector<std::string> types;  ///< every type name its endpoints use (normally one)
  std::vector<Endpoint> writers, readers;
};

/// Listens to the domain's discovery; give it to the participant at creation.
class TopicGraph : public fdds::DomainParticipantListener {
 public:
  /// Every topic seen so far with at least one live endpoint, by name.
  std::map<std::string, TopicSummary> topics() const;
  /// One topic, if any endpoint on it is known.
  std::optional<TopicSummary> topic(const std::string& name) const;
  /// Waits until a writer of `name` is known; the summary, or nothing after the timeout.
  std::optional<TopicSummary> wait_for_writer(const std::string& name,
                                              std::chrono::milliseconds timeout) const;
  /// Names of the live participants (not counting the listener's own).
  std::vector<std::string> participants() const;

  void on_participant_discovery(fdds::DomainParticipant*,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;
  void on_publisher_discovery(fdds::DomainParticipant*,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override;
  void on_subscriber_discovery(fdds::DomainParticipant*,
                               eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override;

 private:
  struct Known {
    std::string topic;
    Endpoint endpoint;
  };
  std::string participant_of(const std::string& guid) const;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::map<std::string, std::string> participants_;  // guid prefix -> name
  std::map<std::string, Known> endpoints_;           // guid -> endpoint
};

/// The QoS a tool's reader should ask for to hear every writer of a topic: reliable and
/// transient local only if every writer offers it.
struct ReaderChoice {
  bool reliable = false;
  bool transient_local = false;
  bool keyed = false;
};
ReaderChoice reader_choice(const TopicSummary& topic);

}  // namespace macsim::topic
