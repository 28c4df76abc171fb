#include "recorded_requests.h"

#include "sim_interfaces/sim_interfaces_dispatch.h"
#include "supervisor/supervisor_dispatch.h"

namespace macsim {

std::shared_ptr<const Request> read_recorded_request(const Command& recorded) {
  const auto* wire = recorded.request_as<WireRequest>();
  if (!wire) return nullptr;
  switch (recorded.source) {
    case CommandSource::Supervisor:
      return SupervisorCall::read(*wire);
    case CommandSource::Ros2Service:
      return sim_interfaces::read_recorded(*wire);
    default:
      return nullptr;  // the runner's own are typed as read; pictures are never recorded
  }
}

}  // namespace macsim
