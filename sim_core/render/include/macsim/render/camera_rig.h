// Renders a robot's stereo cameras on a thread of their own, from scene copies: the physics
// hands over a Scene and goes on; images come back through a callback.
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

#include "macsim/render/renderer.h"

namespace macsim::render {

/// A stereo pair rendered from one scene.
struct StereoFrame {
  double stamp = 0.0;  ///< the scene's sim time
  std::string robot;
  cv::Mat left, right;  ///< BGR
};

/// One render thread for a robot's left and right cameras. submit() never blocks: a scene
/// submitted while the previous one renders replaces any scene still waiting (latest wins).
class CameraRig {
 public:
  using Callback = std::function<void(const StereoFrame&)>;

  CameraRig(const std::string& robot, const CameraIntrinsics& intrinsics, Callback on_frame);
  ~CameraRig();
  CameraRig(const CameraRig&) = delete;
  CameraRig& operator=(const CameraRig&) = delete;

  /// Hands a scene to the render thread.
  void submit(Scene scene);
  /// Blocks until everything submitted so far has been rendered (for lock-step).
  void wait_idle();
  /// Frames rendered so far, and scenes dropped because a newer one came first.
  uint64_t rendered() const;
  uint64_t dropped() const;

 private:
  void run();

  std::string robot_;
  CameraIntrinsics intrinsics_;
  Callback on_frame_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::optional<Scene> pending_;
  bool busy_ = false, stop_ = false;
  uint64_t rendered_ = 0, dropped_ = 0;
  std::thread thread_;
};

}  // namespace macsim::render
