#include "macsim/client/supervisor_client.h"

namespace macsim::client {

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

SimulationClient::Request SimulationClient::request(int32_t command) {
  Request r;
  r.command(command);
  return r;
}

std::optional<SimulationClient::Reply> SimulationClient::step(uint64_t steps,
                                                              std::chrono::milliseconds timeout) {
  Request r = request(macsim_msgs::msg::dds_::SIM_STEP);
  r.steps(steps);
  return call(r, timeout);
}

}  // namespace macsim::client
