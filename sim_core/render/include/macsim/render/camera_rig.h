// Renders a robot's stereo cameras on a thread of their own, from scene copies: the physics
// hands over a Scene and goes on; images come back through a callback.
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "macsim/render/renderer.h"

namespace macsim::render {

/// Which camera of the stereo pair.
enum class Eye { Left, Right };

/// One camera's image of one scene.
struct CameraImage {
  double stamp = 0.0;  ///< the scene's sim time
  std::string robot;
  Eye eye = Eye::Left;
  cv::Mat image;  ///< BGR
};

/// One render thread for a robot's left and right cameras. submit() never blocks: a scene
/// submitted while the previous one renders replaces any scene still waiting (latest wins).
/// Each image goes to the callback as soon as it is rendered (left first, then right).
class CameraRig {
 public:
  using Callback = std::function<void(const CameraImage&)>;

  /// Renders the `eyes` given (both by default; one rig per eye renders them in parallel).
  CameraRig(const std::string& robot, const CameraIntrinsics& intrinsics, Callback on_frame,
            std::vector<Eye> eyes = {Eye::Left, Eye::Right});
  ~CameraRig();
  CameraRig(const CameraRig&) = delete;
  CameraRig& operator=(const CameraRig&) = delete;

  /// Hands a scene to the render thread.
  void submit(Scene scene);
  /// True if nothing waits and nothing renders (a scene submitted now starts at once).
  bool idle() const;
  /// Blocks until everything submitted so far has been rendered (for lock-step).
  void wait_idle();
  /// Stereo frames (scenes) rendered so far, and scenes dropped because a newer one came first.
  uint64_t rendered() const;
  uint64_t dropped() const;

 private:
  void run();

  std::string robot_;
  CameraIntrinsics intrinsics_;
  Callback on_frame_;
  std::vector<Eye> eyes_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::optional<Scene> pending_;
  bool busy_ = false, stop_ = false;
  uint64_t rendered_ = 0, dropped_ = 0;
  std::thread thread_;
};

}  // namespace macsim::render
