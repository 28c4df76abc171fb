// Overview pictures over DDS: a request names a file and a camera mode; the scene is taken on
// the simulation thread between steps (paused or not), rendered offscreen on a thread of its
// own and written as DIR/<name>.png; the reply names the file.
#pragma once

#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "macsim/dds/participant.h"
#include "macsim/msg/macsim_msgsPubSubTypes.h"
#include "macsim/render/renderer.h"
#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/scene.h"
#include "pictures/picture_admission.h"
#include "reply_cache.h"
#include "request_progress.h"
#include "request_service.h"

namespace macsim {

/// Serves PictureRequests; with an empty `folder` every request is refused (pictures off).
class PictureServer {
 public:
  /// Pictures waiting to be taken or rendered at most (each holds a captured scene).
  static constexpr std::size_t kMaxInFlight = 8;
  /// Distinct files written per run at most, by default (macsim --max-pictures).
  static constexpr std::size_t kDefaultMaxFiles = 1000;

  PictureServer(dds::Participant& participant, Runner& runner, std::string folder,
                render::CameraIntrinsics size, std::size_t max_files = kDefaultMaxFiles);
  ~PictureServer();
  PictureServer(const PictureServer&) = delete;
  PictureServer& operator=(const PictureServer&) = delete;

 private:
  using Request = macsim_msgs::msg::dds_::PictureRequest_;
  using Reply = macsim_msgs::msg::dds_::PictureReply_;
  struct Job {
    Request request;
    Scene scene;
    double time = 0;
  };

  void accept(const Request& request);  // Fast DDS's thread
  void send(const Request& request, int code, const std::string& message, double time,
            const std::string& file);
  void render_loop();

  Runner& runner_;
  const std::string folder_;
  const render::CameraIntrinsics size_;
  std::mutex mutex_;
  std::condition_variable queued_;
  std::deque<Job> jobs_;
  PictureAdmission admission_;  // guarded by mutex_
  bool stopping_ = false;
  ReplyCache<Reply> replied_;
  RequestService<macsim_msgs::msg::dds_::PictureRequest_PubSubType,
                 macsim_msgs::msg::dds_::PictureReply_PubSubType>
      service_;                      // requests in, replies out; closed first
  RequestProgress<Reply> progress_;  // writes through service_
  std::thread renderer_;
};

}  // namespace macsim
