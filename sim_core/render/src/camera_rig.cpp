#include "macsim/render/camera_rig.h"

#include "macsim/sim_core/log_sink.h"

namespace macsim::render {

CameraRig::CameraRig(const std::string& robot, const CameraIntrinsics& intrinsics,
                     Callback on_frame, std::vector<Eye> eyes)
    : robot_(robot),
      intrinsics_(intrinsics),
      on_frame_(std::move(on_frame)),
      eyes_(std::move(eyes)),
      thread_([this] { run(); }) {}

CameraRig::~CameraRig() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void CameraRig::submit(Scene scene) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_) ++dropped_;
    pending_ = std::move(scene);
  }
  wake_.notify_one();
}

void CameraRig::wait_idle() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return (!pending_ && !busy_) || stop_; });
}

bool CameraRig::idle() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !pending_ && !busy_;
}

uint64_t CameraRig::rendered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rendered_;
}

uint64_t CameraRig::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

void CameraRig::run() {
  // The GL context belongs to this thread: made, used and destroyed here.
  std::unique_ptr<OffscreenRenderer> renderer;
  try {
    renderer = std::make_unique<OffscreenRenderer>(intrinsics_.width, intrinsics_.height);
  } catch (const RenderError& e) {
    log_message(LogLevel::Error, "camera rig for '" + robot_ + "': " + e.what());
  }
  cv::Mat image;  // reused from frame to frame unless a callback kept the last one
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stop_ || pending_.has_value(); });
    if (stop_) break;
    Scene scene = std::move(*pending_);
    pending_.reset();
    busy_ = true;
    lock.unlock();
    if (renderer) {
      for (const auto& r : scene.robots) {
        if (r.name != robot_) continue;
        for (const Eye eye : eyes_) {
          const Pose& camera = eye == Eye::Left ? r.left_camera : r.right_camera;
          renderer->render_into(image, scene, camera, intrinsics_);
          on_frame_({scene.time, robot_, eye, image});
        }
      }
    }
    lock.lock();
    busy_ = false;
    ++rendered_;
    idle_.notify_all();
  }
  idle_.notify_all();
}

}  // namespace macsim::render
