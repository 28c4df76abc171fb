#include "macsim/client/supervisor_client.h"

#include <unistd.h>

#include <thread>

#include "macsim/dds/topics.h"

namespace macsim::client {

SupervisorClient::SupervisorClient(dds::Participant& participant, std::string client_id)
    : client_id_(client_id.empty() ? "client-" + std::to_string(::getpid()) + "-" +
                                         std::to_string(reinterpret_cast<uintptr_t>(this) % 100000)
                                   : std::move(client_id)),
      requests_(participant, dds::topics::kSupervisorRequest, dds::QosFamily::Command),
      replies_(participant, dds::topics::kSupervisorReply, dds::QosFamily::Command,
               [this](const Reply& r) {
                 std::lock_guard<std::mutex> lock(mutex_);
                 if (r.client_id() != client_id_ || r.sequence_number() != waiting_for_) return;
                 reply_ = r;
                 replied_.notify_all();
               }) {}

SupervisorClient::Request SupervisorClient::request(int32_t operation, uint32_t object_id,
                                                    std::initializer_list<double> values) {
  Request r;
  r.operation(operation);
  r.object_id(object_id);
  std::size_t i = 0;
  for (double v : values) {
    if (i < r.values().size()) r.values()[i++] = v;
  }
  return r;
}

bool SupervisorClient::wait_for_server(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (requests_.matched() == 0 || replies_.matched() == 0) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

std::optional<SupervisorClient::Reply> SupervisorClient::call(Request request,
                                                               std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  if (!wait_for_server(timeout)) return std::nullopt;
  request.client_id(client_id_);
  request.sequence_number(next_sequence_++);
  std::unique_lock<std::mutex> lock(mutex_);
  waiting_for_ = request.sequence_number();
  reply_.reset();
  while (std::chrono::steady_clock::now() < deadline) {
    lock.unlock();
    requests_.write(request);
    lock.lock();
    const auto retry = std::min(deadline, std::chrono::steady_clock::now() + std::chrono::seconds(1));
    if (replied_.wait_until(lock, retry, [this] { return reply_.has_value(); })) return reply_;
  }
  return std::nullopt;
}

}  // namespace macsim::client
