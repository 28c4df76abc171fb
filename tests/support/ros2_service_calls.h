// Calls to macsim's ROS 2 services (/macsim/<service>) as an rmw_fastrtps_cpp client makes
// them: one client per service, made on first use and kept; a service not served or a call
// not answered is a test failure (and an empty response).
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>

#include "macsim/dds/ros2_service.h"

namespace macsim::test {

/// The service clients of one test participant.
class Ros2ServiceCalls {
 public:
  explicit Ros2ServiceCalls(dds::Participant& participant) : participant_(participant) {}

  /// Calls /macsim/<service> once its server is seen.
  template <class Req, class Resp>
  typename Resp::type call(const std::string& service, const typename Req::type& request) {
    using Client = dds::ServiceClient<Req, Resp>;
    auto& slot = clients_[service];
    if (!slot) {
      auto client = std::make_shared<Client>(participant_, "/macsim/" + service);
      EXPECT_TRUE(client->wait_for_service(std::chrono::seconds(10)))
          << service << " is not served";
      slot = client;
    }
    auto reply = std::static_pointer_cast<Client>(slot)->call(request, std::chrono::seconds(30));
    EXPECT_TRUE(reply.has_value()) << service << ": no reply";
    return reply.value_or(typename Resp::type{});
  }

 private:
  dds::Participant& participant_;
  std::map<std::string, std::shared_ptr<void>> clients_;
};

}  // namespace macsim::test
