// Offscreen OpenGL rendering on the CPU (EGL surfaceless + llvmpipe): images as cv::Mat.
#pragma once

#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "macsim/sim_core/scene.h"

namespace macsim::render {

/// A pinhole camera: image size and vertical field of view.
struct CameraIntrinsics {
  int width = 640;
  int height = 480;
  double fov_y = 45.0 * M_PI / 180.0;  ///< rad
  double near_clip = 0.03, far_clip = 60.0;
  /// Focal length in pixels.
  double focal() const;
};

/// Raised when no offscreen GL context can be made; says why.
struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Draws scenes into images. One GL context of its own: use it from one thread at a time.
class OffscreenRenderer {
 public:
  /// Creates an EGL surfaceless context and a framebuffer of that size.
  OffscreenRenderer(int width, int height);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  /// The scene seen from `camera` (x forward, y left, z up): a BGR image; with `depth`, also
  /// the metric depth along the view axis (CV_32F, far_clip where nothing is).
  cv::Mat render(const Scene& scene, const Pose& camera, const CameraIntrinsics& intrinsics,
                 cv::Mat* depth = nullptr);
  /// The same into `image`, whose storage is reused when it has the size and nobody shares it.
  void render_into(cv::Mat& image, const Scene& scene, const Pose& camera,
                   const CameraIntrinsics& intrinsics, cv::Mat* depth = nullptr);
  /// "llvmpipe (LLVM 15.0.6, 256 bits)" or the like.
  std::string gl_renderer() const;

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
  int width_, height_;
};

}  // namespace macsim::render
