// An interactive window on a world (needs an X display), with the seed's camera modes and
// mouse and keyboard controls; and the free camera those controls move.
#pragma once

#include <functional>
#include <string>

#include "macsim/render/camera_modes.h"
#include "macsim/render/renderer.h"

namespace macsim::render {

/// Mouse buttons as the seed's viewer uses them.
enum class MouseButton { Left, Middle, Right };

/// The user's camera in the free modes: a position, a heading (yaw about z) and a tilt
/// (pitch, positive looks down).
struct FreeCamera {
  Eigen::Vector3d position = Eigen::Vector3d(-4, -4, 3);
  double yaw = M_PI / 4;
  double pitch = 0.45;

  Pose pose() const;
  static FreeCamera from_pose(const Pose& pose);
  /// A mouse drag of (dx, dy) pixels (dy > 0: downwards), as in MACSim's MouseOnly mode: the
  /// left button pans and tilts; the right one moves in the ground plane (up/down along the
  /// view, left/right across it); the middle one raises or lowers (up/down) and moves across.
  void drag(MouseButton button, double dx, double dy);
  /// w, a, s, d: forwards, left, backwards, right in the ground plane by `step` metres.
  /// Returns false for any other key.
  bool key(char key, double step = 0.1);
};

/// What the window shows and how.
struct ViewerOptions {
  int width = 960, height = 720;
  CameraMode mode = CameraMode::MouseKeyboard;
  std::string screenshot;          ///< write the window's image here once, then go on
  double screenshot_after = 1.0;   ///< s of wall time before the screenshot
};

/// Opens the window and shows the newest scene until it is closed (q, Esc, the window's close
/// button) or `stop()` returns true. Keys 1 to 8 pick the camera modes in the seed's order.
/// Returns 0, or 1 with a message on stderr if no window can be opened or the screenshot asked
/// for cannot be written (the window then closes).
int run_viewer(const ViewerOptions& options, const std::function<Scene()>& latest_scene,
               const std::function<bool()>& stop);

}  // namespace macsim::render
