#include "macsim/client/supervisor_client.h"

namespace macsim::client {

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
