#include "topic_graph.h"

#include <fastdds/rtps/builtin/data/ParticipantProxyData.h>
#include <fastdds/rtps/builtin/data/ReaderProxyData.h>
#include <fastdds/rtps/builtin/data/WriterProxyData.h>
#include <fastdds/rtps/participant/ParticipantDiscoveryInfo.h>
#include <fastdds/rtps/reader/ReaderDiscoveryInfo.h>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>

#include <algorithm>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <sstream>

namespace macsim::topic {

namespace rtps = eprosima::fastrtps::rtps;

namespace {

template <class Printable>
std::string text(const Printable& value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace

void TopicGraph::on_participant_discovery(fdds::DomainParticipant*,
                                          rtps::ParticipantDiscoveryInfo&& info) {
  const std::string prefix = text(info.info.m_guid.guidPrefix);
  std::lock_guard<std::mutex> lock(mutex_);
  if (info.status == rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT ||
      info.status == rtps::ParticipantDiscoveryInfo::CHANGED_QOS_PARTICIPANT) {
    participants_[prefix] = info.info.m_participantName.to_string();
  } else {
    participants_.erase(prefix);
    for (auto it = endpoints_.begin(); it != endpoints_.end();) {
      it = it->first.rfind(prefix, 0) == 0 ? endpoints_.erase(it) : std::next(it);
    }
  }
  changed_.notify_all();
}

std::string TopicGraph::participant_of(const std::string& guid) const {
  const auto prefix = guid.substr(0, guid.rfind('|'));
  auto found = participants_.find(prefix);
  return found == participants_.end() ? std::string("?") : found->second;
}

void TopicGraph::on_publisher_discovery(fdds::DomainParticipant* participant,
                                        rtps::WriterDiscoveryInfo&& info) {
  // Fast DDS reports the listening participant's own endpoints too: they are not the domain's.
  if (participant && info.info.guid().guidPrefix == participant->guid().guidPrefix) return;
  const std::string guid = text(info.info.guid());
  std::lock_guard<std::mutex> lock(mutex_);
  if (info.status == rtps::WriterDiscoveryInfo::REMOVED_WRITER) {
    endpoints_.erase(guid);
  } else {
    Endpoint e;
    e.guid = guid;
    e.participant = participant_of(guid);
    e.type = info.info.typeName().to_string();
    e.writer = true;
    e.reliable = info.info.m_qos.m_reliability.kind == fdds::RELIABLE_RELIABILITY_QOS;
    e.transient_local = info.info.m_qos.m_durability.kind != fdds::VOLATILE_DURABILITY_QOS;
    e.keyed = info.info.topicKind() == rtps::WITH_KEY;
    endpoints_[guid] = {info.info.topicName().to_string(), e};
  }
  changed_.notify_all();
}

void TopicGraph::on_subscriber_discovery(fdds::DomainParticipant* participant,
                                         rtps::ReaderDiscoveryInfo&& info) {
  if (participant && info.info.guid().guidPrefix == participant->guid().guidPrefix) return;
  const std::string guid = text(info.info.guid());
  std::lock_guard<std::mutex> lock(mutex_);
  if (info.status == rtps::ReaderDiscoveryInfo::REMOVED_READER) {
    endpoints_.erase(guid);
  } else {
    Endpoint e;
    e.guid = guid;
    e.participant = participant_of(guid);
    e.type = info.info.typeName().to_string();
    e.reliable = info.info.m_qos.m_reliability.kind == fdds::RELIABLE_RELIABILITY_QOS;
    e.transient_local = info.info.m_qos.m_durability.kind != fdds::VOLATILE_DURABILITY_QOS;
    e.keyed = info.info.topicKind() == rtps::WITH_KEY;
    endpoints_[guid] = {info.info.topicName().to_string(), e};
  }
  changed_.notify_all();
}

std::map<std::string, TopicSummary> TopicGraph::topics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<std::string, TopicSummary> out;
  for (const auto& [guid, known] : endpoints_) {
    TopicSummary& t = out[known.topic];
    t.name = known.topic;
    Endpoint e = known.endpoint;
    if (e.participant == "?") e.participant = participant_of(guid);
    if (std::find(t.types.begin(), t.types.end(), e.type) == t.types.end()) {
      t.types.push_back(e.type);
    }
    (e.writer ? t.writers : t.readers).push_back(e);
  }
  return out;
}

std::optional<TopicSummary> TopicGraph::topic(const std::string& name) const {
  auto all = topics();
  auto found = all.find(name);
  if (found == all.end()) return std::nullopt;
  return found->second;
}

std::optional<TopicSummary> TopicGraph::wait_for_writer(const std::string& name,
                                                        std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    auto found = topic(name);
    if (found && !found->writers.empty()) return found;
    std::unique_lock<std::mutex> lock(mutex_);
    if (changed_.wait_until(lock, deadline) == std::cv_status::timeout) {
      lock.unlock();
      found = topic(name);
      if (found && !found->writers.empty()) return found;
      return std::nullopt;
    }
  }
}

std::vector<std::string> TopicGraph::participants() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> names;
  for (const auto& [prefix, name] : participants_) names.push_back(name);
  std::sort(names.begin(), names.end());
  return names;
}

ReaderChoice reader_choice(const TopicSummary& topic) {
  ReaderChoice choice;
  choice.reliable = !topic.writers.empty();
  choice.transient_local = !topic.writers.empty();
  for (const auto& w : topic.writers) {
    choice.reliable = choice.reliable && w.reliable;
    choice.transient_local = choice.transient_local && w.transient_local;
    choice.keyed = choice.keyed || w.keyed;
  }
  for (const auto& r : topic.readers) choice.keyed = choice.keyed || r.keyed;
  return choice;
}

}  // namespace macsim::topic
