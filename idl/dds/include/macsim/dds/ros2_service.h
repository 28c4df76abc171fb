// ROS 2 services over plain Fast DDS, on the wire as rmw_fastrtps_cpp (Jazzy's default RMW) puts
// them: requests on rq/<service>Request, replies on rr/<service>Reply (reliable, volatile, keep
// last 10), each reply tied to its request by the sample identity it names as related.
#pragma once

#include <fastrtps/rtps/common/WriteParams.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "macsim/dds/participant.h"

namespace macsim::dds {

/// DDS topic of a service's requests: "/macsim/step_simulation" ->
/// "rq/macsim/step_simulationRequest".
std::string service_request_topic(const std::string& service);
/// DDS topic of a service's replies: "rr/<service>Reply".
std::string service_reply_topic(const std::string& service);

/// One request of one client: the client's reply reader (or request writer) and the request's
/// sequence number, as rmw_fastrtps correlates them.
using RequestId = eprosima::fastrtps::rtps::SampleIdentity;

/// The request and reply topics of a service named outright (this project's own services).
struct ServiceTopics {
  std::string request, reply;
};

/// Serves one service: `on_request` hears each request on Fast DDS's thread (copy or enqueue it
/// there, nothing more); `reply` answers it later from any thread. The one request/reply
/// transport of every service macsim serves: the ROS 2 services (correlated by sample identity,
/// as rmw_fastrtps does) and its own (correlated in the payload, client id and sequence number
/// echoed; their replies name the request's sample identity too when it is known).
template <class RequestType, class ResponseType>
class ServiceServer : private fdds::DataReaderListener, private fdds::DataWriterListener {
 public:
  using Request = typename RequestType::type;
  using Response = typename ResponseType::type;
  using Handler = std::function<void(const Request&, const RequestId&)>;

  /// A ROS 2 service ("/macsim/step_simulation": rq/macsim/step_simulationRequest, ...).
  ServiceServer(Participant& participant, const std::string& service, Handler on_request)
      : ServiceServer(participant, service,
                      {service_request_topic(service), service_reply_topic(service)},
                      std::move(on_request)) {}
  /// A service on topics named outright.
  ServiceServer(Participant& participant, const ServiceTopics& topics, Handler on_request)
      : ServiceServer(participant, topics.request, topics, std::move(on_request)) {}
  ~ServiceServer() override {
    reader_->set_listener(nullptr);
    writer_->set_listener(nullptr);
    participant_.subscriber()->delete_datareader(reader_);
    participant_.publisher()->delete_datawriter(writer_);
    participant_.endpoints_changed();
  }
  ServiceServer(const ServiceServer&) = delete;
  ServiceServer& operator=(const ServiceServer&) = delete;

  /// Answers a request. A reply to a client whose reply reader is not matched yet is held
  /// until it matches (at most 10 s), as a volatile writer would otherwise send it to no one.
  void reply(const RequestId& id, const Response& response) {
    const auto& client = id.writer_guid();
    const bool is_reader = (client.entityId.value[3] & 0x04) != 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto now = std::chrono::steady_clock::now();
      for (auto it = pending_.begin(); it != pending_.end();) {
        it = now - it->since > std::chrono::seconds(10) ? pending_.erase(it) : std::next(it);
      }
      if (is_reader && !matched_.count(client)) {
        pending_.push_back({id, response, now});
        return;
      }
    }
    send(id, response);  // never under mutex_: Fast DDS may hold its lock while it calls us
  }
  /// Writes a reply correlated in its payload alone (e.g. a progress reply).
  void publish(const Response& response) { send({}, response); }
  /// The service's name, e.g. "/macsim/step_simulation".
  const std::string& name() const { return service_; }

 private:
  ServiceServer(Participant& participant, const std::string& service, const ServiceTopics& topics,
                Handler on_request)
      : participant_(participant), service_(service), on_request_(std::move(on_request)) {
    writer_ = participant.publisher()->create_datawriter(
        participant.topic<ResponseType>(topics.reply),
        writer_qos(QosFamily::Request, participant.publisher()), this,
        fdds::StatusMask::publication_matched());
    reader_ = participant.subscriber()->create_datareader(
        participant.topic<RequestType>(topics.request),
        reader_qos(QosFamily::Request, participant.subscriber()), this);
    if (!writer_ || !reader_) throw DdsError("cannot serve the service " + service);
    participant.endpoints_changed();
  }

  struct Pending {
    RequestId id;
    Response response;
    std::chrono::steady_clock::time_point since;
  };

  void send(const RequestId& id, const Response& response) {
    eprosima::fastrtps::rtps::WriteParams params;
    params.related_sample_identity(id);
    writer_->write(const_cast<Response*>(&response), params);
  }
  void on_data_available(fdds::DataReader* reader) override {
    Request request;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&request, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      RequestId id = info.sample_identity;
      // rmw_fastrtps clients name their reply reader as the related writer: reply to it.
      if (info.related_sample_identity.writer_guid() != eprosima::fastrtps::rtps::c_Guid_Unknown) {
        id.writer_guid(info.related_sample_identity.writer_guid());
      }
      on_request_(request, id);
    }
  }
  void on_publication_matched(fdds::DataWriter*,
                              const fdds::PublicationMatchedStatus& status) override {
    eprosima::fastrtps::rtps::GUID_t reader;
    eprosima::fastrtps::rtps::iHandle2GUID(reader, status.last_subscription_handle);
    std::vector<Pending> due;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (status.current_count_change < 0) {
        matched_.erase(reader);
        return;
      }
      matched_.insert(reader);
      for (auto it = pending_.begin(); it != pending_.end();) {
        if (it->id.writer_guid() == reader) {
          due.push_back(std::move(*it));
          it = pending_.erase(it);
        } else {
          ++it;
        }
      }
    }
    for (const Pending& p : due) send(p.id, p.response);
  }

  Participant& participant_;
  std::string service_;
  Handler on_request_;
  std::mutex mutex_;  // guards matched_ and pending_
  std::set<eprosima::fastrtps::rtps::GUID_t> matched_;
  std::vector<Pending> pending_;
  fdds::DataWriter* writer_ = nullptr;
  fdds::DataReader* reader_ = nullptr;
};

/// Calls one ROS 2 service as an rmw_fastrtps client does: the request names the client's
/// reply reader as related writer; a reply is ours if it names that reader (or our request
/// writer) back, with our request's sequence number.
template <class RequestType, class ResponseType>
class ServiceClient : private fdds::DataReaderListener {
 public:
  using Request = typename RequestType::type;
  using Response = typename ResponseType::type;

  ServiceClient(Participant& participant, const std::string& service) : participant_(participant) {
    writer_ = participant.publisher()->create_datawriter(
        participant.topic<RequestType>(service_request_topic(service)),
        writer_qos(QosFamily::Request, participant.publisher()));
    reader_ = participant.subscriber()->create_datareader(
        participant.topic<ResponseType>(service_reply_topic(service)),
        reader_qos(QosFamily::Request, participant.subscriber()), this);
    if (!writer_ || !reader_) throw DdsError("cannot be a client of the service " + service);
    participant.endpoints_changed();
  }
  ~ServiceClient() override {
    reader_->set_listener(nullptr);
    participant_.subscriber()->delete_datareader(reader_);
    participant_.publisher()->delete_datawriter(writer_);
    participant_.endpoints_changed();
  }
  ServiceClient(const ServiceClient&) = delete;
  ServiceClient& operator=(const ServiceClient&) = delete;

  /// True once a server's request reader and reply writer both matched ours (rmw's
  /// service_server_is_available), waiting at most `timeout`. Discovery is not simultaneous on
  /// both sides: a request written before the server's reader has matched our writer is
  /// dropped by that (volatile) reader, so this also gives the server's side time to match.
  bool wait_for_service(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      fdds::PublicationMatchedStatus pub;
      fdds::SubscriptionMatchedStatus sub;
      writer_->get_publication_matched_status(pub);
      reader_->get_subscription_matched_status(sub);
      if (pub.current_count > 0 && sub.current_count > 0) {
        if (!settled_) std::this_thread::sleep_for(std::chrono::milliseconds(250));
        settled_ = true;
        return true;
      }
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  /// Sends a request and waits for its reply; nothing after the timeout.
  std::optional<Response> call(const Request& request, std::chrono::milliseconds timeout) {
    eprosima::fastrtps::rtps::WriteParams params;
    params.related_sample_identity().writer_guid(reader_->guid());
    std::unique_lock<std::mutex> lock(mutex_);
    if (!writer_->write(const_cast<Request*>(&request), params)) return std::nullopt;
    const auto sequence = params.sample_identity().sequence_number();
    const bool answered =
        replied_.wait_for(lock, timeout, [&] { return replies_.count(sequence); });
    if (!answered) return std::nullopt;
    Response response = std::move(replies_[sequence]);
    replies_.erase(sequence);
    return response;
  }

 private:
  void on_data_available(fdds::DataReader* reader) override {
    Response response;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&response, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      const auto& to = info.related_sample_identity.writer_guid();
      if (to != reader_->guid() && to != writer_->guid()) continue;  // another client's
      std::lock_guard<std::mutex> lock(mutex_);
      replies_[info.related_sample_identity.sequence_number()] = std::move(response);
      replied_.notify_all();
    }
  }

  Participant& participant_;
  bool settled_ = false;  // the server's side had time to match ours
  std::mutex mutex_;
  std::condition_variable replied_;
  std::map<eprosima::fastrtps::rtps::SequenceNumber_t, Response> replies_;
  fdds::DataWriter* writer_ = nullptr;
  fdds::DataReader* reader_ = nullptr;
};

}  // namespace macsim::dds
