// Draws a Scene with legacy OpenGL into whatever context is current (offscreen or a window).
#pragma once

#include <map>
#include <string>

#include "macsim/render/renderer.h"

namespace macsim::render::detail {

/// Display lists of the unit shapes, texture cache, lights and the floor, for one GL context.
class SceneDrawer {
 public:
  /// Needs the context it will draw into to be current.
  SceneDrawer();
  /// Draws `scene` seen from `camera` into the current viewport of `width` x `height`.
  void draw(const Scene& scene, const Pose& camera, const CameraIntrinsics& intrinsics);

 private:
  unsigned texture(const std::string& path);
  unsigned upload(const cv::Mat& bgr);

  unsigned box_ = 0, cylinder_ = 0, sphere_ = 0;
  unsigned floor_texture_ = 0;
  std::map<std::string, unsigned> textures_;
};

}  // namespace macsim::render::detail
