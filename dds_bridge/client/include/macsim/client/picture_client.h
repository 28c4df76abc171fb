// Asks a simulator for overview pictures (one of its camera modes, offscreen, to a PNG file).
#pragma once

#include "macsim/client/request_reply.h"
#include "macsim/dds/topics.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"

namespace macsim::client {

/// Calls the simulator's picture service (macsim --pictures DIR).
class PictureClient : public RequestReply<macsim_msgs::msg::dds_::PictureRequest_PubSubType,
                                          macsim_msgs::msg::dds_::PictureReply_PubSubType> {
 public:
  explicit PictureClient(dds::Participant& participant, std::string client_id = "")
      : RequestReply(participant, dds::topics::kPictureRequest, dds::topics::kPictureReply,
                     std::move(client_id)) {}

  /// Asks for DIR/<name>.png seen from `camera_mode`; nothing if no simulator answered within
  /// `timeout` (a real robot has no picture service).
  std::optional<Reply> take(const std::string& name, const std::string& camera_mode = "Follow",
                            std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    Request request;
    request.name(name);
    request.camera_mode(camera_mode);
    return call(request, timeout);
  }
};

}  // namespace macsim::client
