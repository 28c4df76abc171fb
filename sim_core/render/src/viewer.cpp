#include "macsim/render/viewer.h"

#include <GL/freeglut.h>

#include <chrono>
#include <cstdlib>
#include <string>

#include "macsim/images/image_files.h"
#include "macsim/sim_core/log_sink.h"
#include "scene_drawer.h"

namespace macsim::render {

namespace {

// GLUT calls back into plain functions: the one open viewer's state lives here.
struct ViewerState {
  ViewerOptions options;
  std::function<Scene()> latest_scene;
  FreeCamera camera;
  bool camera_placed = false;
  std::unique_ptr<detail::SceneDrawer> drawer;
  int button = -1, last_x = 0, last_y = 0;
  bool close = false;
  bool shot = false;
  bool failed = false;  // the screenshot asked for could not be written
  std::chrono::steady_clock::time_point opened;
};

ViewerState* g_state = nullptr;

bool free_mode(CameraMode mode) {
  return mode == CameraMode::MouseOnly || mode == CameraMode::MouseKeyboard ||
         mode == CameraMode::FixedFollow;
}

void display() {
  ViewerState& s = *g_state;
  const Scene scene = s.latest_scene();
  if (!s.camera_placed) {
    s.camera = FreeCamera::from_pose(camera_pose(CameraMode::Manual, scene));
    s.camera_placed = true;
  }
  CameraIntrinsics in;
  in.width = glutGet(GLUT_WINDOW_WIDTH);
  in.height = glutGet(GLUT_WINDOW_HEIGHT);
  glViewport(0, 0, in.width, in.height);
  s.drawer->draw(scene, camera_pose(s.options.mode, scene, s.camera.pose()), in);
  const double open_for =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - s.opened).count();
  if (!s.options.screenshot.empty() && !s.shot && open_for >= s.options.screenshot_after) {
    cv::Mat image(in.height, in.width, CV_8UC3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, in.width, in.height, GL_BGR, GL_UNSIGNED_BYTE, image.data);
    cv::flip(image, image, 0);
    s.shot = true;
    std::string problem;
    try {
      if (!images::write_image(s.options.screenshot, image)) problem = "cannot write it";
    } catch (const images::CodecsUnavailable& e) {
      problem = e.what();
    }
    if (problem.empty()) {
      log_message(LogLevel::Info, "viewer: wrote a screenshot to " + s.options.screenshot);
    } else {
      log_message(LogLevel::Error, "viewer: no screenshot to " + s.options.screenshot + ": " + problem);
      s.failed = s.close = true;  // the window closes and the viewer says it failed
    }
  }
  glutSwapBuffers();
}

void mouse(int button, int state, int x, int y) {
  g_state->button = state == GLUT_DOWN ? button : -1;
  g_state->last_x = x;
  g_state->last_y = y;
}

void motion(int x, int y) {
  ViewerState& s = *g_state;
  const int dx = x - s.last_x, dy = y - s.last_y;
  s.last_x = x;
  s.last_y = y;
  if (!free_mode(s.options.mode)) return;  // Follow, Inside, the cameras, Manual: no mouse
  if (s.button == GLUT_LEFT_BUTTON) s.camera.drag(MouseButton::Left, dx, dy);
  if (s.button == GLUT_RIGHT_BUTTON) s.camera.drag(MouseButton::Right, dx, dy);
  if (s.button == GLUT_MIDDLE_BUTTON) s.camera.drag(MouseButton::Middle, dx, dy);
}

void keyboard(unsigned char key, int, int) {
  ViewerState& s = *g_state;
  if (key == 'q' || key == 27) {
    s.close = true;
  } else if (key >= '1' && key <= '9') {
    s.options.mode = static_cast<CameraMode>(key - '1');
    glutSetWindowTitle(("MACSim-DDS: " + camera_mode_name(s.options.mode)).c_str());
  } else if (s.options.mode == CameraMode::MouseKeyboard) {
    s.camera.key(static_cast<char>(key));
  }
}

}  // namespace

int run_viewer(const ViewerOptions& options, const std::function<Scene()>& latest_scene,
               const std::function<bool()>& stop) {
  if (!std::getenv("DISPLAY")) {
    log_message(LogLevel::Error,
                "viewer: no X display (DISPLAY is not set); render offscreen with --snapshot");
    return 1;
  }
  int argc = 1;
  char name[] = "macsim";
  char* argv[] = {name, nullptr};
  glutInit(&argc, argv);
  glutSetOption(GLUT_ACTION_ON_WINDOW_CLOSE, GLUT_ACTION_CONTINUE_EXECUTION);
  glutInitDisplayMode(GLUT_DOUBLE | GLUT_RGB | GLUT_DEPTH);
  glutInitWindowSize(options.width, options.height);
  const int window = glutCreateWindow(("MACSim-DDS: " + camera_mode_name(options.mode)).c_str());
  if (window <= 0) {
    log_message(LogLevel::Error, "viewer: cannot open a window");
    return 1;
  }
  ViewerState state;
  state.options = options;
  state.latest_scene = latest_scene;
  state.drawer = std::make_unique<detail::SceneDrawer>();
  state.opened = std::chrono::steady_clock::now();
  g_state = &state;
  glutDisplayFunc(display);
  glutMouseFunc(mouse);
  glutMotionFunc(motion);
  glutKeyboardFunc(keyboard);
  log_message(LogLevel::Info, "viewer: keys 1-9 camera modes (" + camera_mode_name(options.mode) +
                                  " now), w/a/s/d move, q quits; mouse: left pans, right moves, "
                                  "middle lifts");
  while (!state.close && !stop() && glutGetWindow() != 0) {
    glutPostRedisplay();
    glutMainLoopEvent();
  }
  if (glutGetWindow() != 0) glutDestroyWindow(window);
  glutMainLoopEvent();
  g_state = nullptr;
  return state.failed ? 1 : 0;
}

}  // namespace macsim::render
