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

std::optional<SimulationClient::Reply> SimulationClient::cancel(uint64_t sequence_number,
                                                                std::chrono::milliseconds timeout) {
  Request r = request(macsim_msgs::msg::dds_::SIM_CANCEL);
  r.cancel_sequence_number(sequence_number);
  return call(r, timeout);
}

namespace step_until {

namespace mm = macsim_msgs::msg::dds_;

SimulationClient::Request request(uint64_t steps, uint32_t check_every, uint32_t options) {
  auto r = SimulationClient::request(mm::SIM_STEP);
  r.steps(steps);
  r.check_every(check_every);
  r.step_options(options);
  return r;
}

Condition reading(int32_t what, uint32_t object_id) {
  Condition c;
  c.reading(what);
  c.object_id(object_id);
  return c;
}

namespace {
Condition test(int32_t what, int32_t how, double value, double tolerance, int32_t group,
               uint32_t object_id) {
  Condition c = reading(what, object_id);
  c.test(how);
  c.value(value);
  c.tolerance(tolerance);
  c.group(group);
  return c;
}
}  // namespace

Condition above(int32_t what, double value, int32_t group, uint32_t object_id) {
  return test(what, mm::STEP_TEST_ABOVE, value, 0, group, object_id);
}
Condition below(int32_t what, double value, int32_t group, uint32_t object_id) {
  return test(what, mm::STEP_TEST_BELOW, value, 0, group, object_id);
}
Condition near(int32_t what, double value, double tolerance, int32_t group) {
  return test(what, mm::STEP_TEST_NEAR, value, tolerance, group, 0);
}
Condition stalled(int32_t what, double seconds, double rise, int32_t group) {
  return test(what, mm::STEP_TEST_STALLED, seconds, rise, group, 0);
}

}  // namespace step_until

}  // namespace macsim::client
