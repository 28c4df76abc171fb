// Draws a Scene with legacy OpenGL into whatever context is current (offscreen or a window).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "macsim/render/renderer.h"

namespace macsim::render::detail {

/// Display lists of the unit shapes, texture cache, lights and the floor, for one GL context.
class SceneDrawer {
 public:
  /// Textures kept at most (files that would not load count too): beyond, the least recently
  /// drawn go after a draw, never one the scene just drawn uses.
  static constexpr std::size_t kMaxTextures = 64;
  /// Texture bytes kept at most, likewise.
  static constexpr std::size_t kMaxTextureBytes = std::size_t{256} << 20;

  /// Needs the context it will draw into to be current.
  SceneDrawer();
  /// Which way the framebuffer's rows run once drawn: GL's own (bottom-up, a window's) or an
  /// image's (top-down: glReadPixels then gives an image with no flip).
  enum class Rows { BottomUp, TopDown };
  /// Draws `scene` seen from `camera` into the current viewport of `width` x `height`.
  void draw(const Scene& scene, const Pose& camera, const CameraIntrinsics& intrinsics,
            Rows rows = Rows::BottomUp);

 private:
  unsigned texture(const std::string& path);
  unsigned upload(const cv::Mat& bgr);
  /// Deletes the least recently drawn textures while over a cap.
  void trim_textures();

  struct Texture {
    unsigned id = 0;        // 0: the file would not load
    std::size_t bytes = 0;  // of the image uploaded
    uint64_t drawn = 0;     // the draw that used it last
  };
  unsigned box_ = 0, cylinder_ = 0, sphere_ = 0;
  unsigned floor_texture_ = 0;
  std::map<std::string, Texture> textures_;  // by path
  std::size_t texture_bytes_ = 0;            // of textures_
  uint64_t draws_ = 0;
};

}  // namespace macsim::render::detail
