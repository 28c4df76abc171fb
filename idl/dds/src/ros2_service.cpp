#include "macsim/dds/ros2_service.h"

namespace macsim::dds {

namespace {
/// The ROS name without its leading '/': rmw adds the prefix and the suffix around it.
std::string bare(const std::string& service) {
  return !service.empty() && service.front() == '/' ? service.substr(1) : service;
}
}  // namespace

std::string service_request_topic(const std::string& service) {
  return "rq/" + bare(service) + "Request";
}

std::string service_reply_topic(const std::string& service) {
  return "rr/" + bare(service) + "Reply";
}

}  // namespace macsim::dds
