#include "macsim/render/renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace macsim::render {

double CameraIntrinsics::focal() const { return height / 2.0 / std::tan(fov_y / 2); }

namespace {

constexpr int kSegments = 24;

void unit_box() {
  // The cube [-0.5, 0.5]^3, one quad a face with its normal and texture coordinates.
  static const float faces[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static const float corners[6][4][3] = {
      {{0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, {0.5f, -0.5f, 0.5f}},
      {{-0.5f, 0.5f, -0.5f}, {-0.5f, -0.5f, -0.5f}, {-0.5f, -0.5f, 0.5f}, {-0.5f, 0.5f, 0.5f}},
      {{0.5f, 0.5f, -0.5f}, {-0.5f, 0.5f, -0.5f}, {-0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}},
      {{-0.5f, -0.5f, -0.5f}, {0.5f, -0.5f, -0.5f}, {0.5f, -0.5f, 0.5f}, {-0.5f, -0.5f, 0.5f}},
      {{-0.5f, -0.5f, 0.5f}, {0.5f, -0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, {-0.5f, 0.5f, 0.5f}},
      {{-0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, -0.5f}, {0.5f, -0.5f, -0.5f}, {-0.5f, -0.5f, -0.5f}}};
  static const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  glBegin(GL_QUADS);
  for (int f = 0; f < 6; ++f) {
    glNormal3fv(faces[f]);
    for (int k = 0; k < 4; ++k) {
      glTexCoord2fv(uv[k]);
      glVertex3fv(corners[f][k]);
    }
  }
  glEnd();
}

void unit_cylinder() {
  // Radius 1, height 1 along z, centred.
  glBegin(GL_QUAD_STRIP);
  for (int i = 0; i <= kSegments; ++i) {
    const float a = 2 * M_PI * i / kSegments, x = std::cos(a), y = std::sin(a);
    glNormal3f(x, y, 0);
    glTexCoord2f(float(i) / kSegments, 1);
    glVertex3f(x, y, 0.5f);
    glTexCoord2f(float(i) / kSegments, 0);
    glVertex3f(x, y, -0.5f);
  }
  glEnd();
  for (float z : {0.5f, -0.5f}) {
    glBegin(GL_TRIANGLE_FAN);
    glNormal3f(0, 0, z > 0 ? 1 : -1);
    glTexCoord2f(0.5f, 0.5f);
    glVertex3f(0, 0, z);
    for (int i = 0; i <= kSegments; ++i) {
      const float a = 2 * M_PI * (z > 0 ? i : kSegments - i) / kSegments;
      glTexCoord2f(0.5f + 0.5f * std::cos(a), 0.5f + 0.5f * std::sin(a));
      glVertex3f(std::cos(a), std::sin(a), z);
    }
    glEnd();
  }
}

void unit_sphere() {
  const int stacks = kSegments / 2;
  for (int j = 0; j < stacks; ++j) {
    const float t0 = M_PI * j / stacks - M_PI / 2, t1 = M_PI * (j + 1) / stacks - M_PI / 2;
    glBegin(GL_QUAD_STRIP);
    for (int i = 0; i <= kSegments; ++i) {
      const float a = 2 * M_PI * i / kSegments;
      for (float t : {t1, t0}) {
        const float x = std::cos(t) * std::cos(a), y = std::cos(t) * std::sin(a), z = std::sin(t);
        glNormal3f(x, y, z);
        glTexCoord2f(float(i) / kSegments, (t + M_PI / 2) / M_PI);
        glVertex3f(x, y, z);
      }
    }
    glEnd();
  }
}

/// Column-major 4x4 of a pose, for glMultMatrixd.
void pose_matrix(const Pose& pose, double out[16]) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = pose.orientation.toRotationMatrix();
  m.topRightCorner<3, 1>() = pose.position;
  Eigen::Map<Eigen::Matrix4d> column_major(out);
  column_major = m;
}

}  // namespace

struct OffscreenRenderer::Gl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  GLuint fbo = 0, color = 0, depth = 0;
  GLuint box = 0, cylinder = 0, sphere = 0;  // display lists
  GLuint floor_texture = 0;
  std::map<std::string, GLuint> textures;

  void make_current() const {
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      throw RenderError("eglMakeCurrent failed");
    }
  }

  GLuint upload(const cv::Mat& bgr) {
    GLuint id;
    glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_2D, id);
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    cv::flip(rgb, rgb, 0);  // images run top-down, GL textures bottom-up
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, rgb.cols, rgb.rows, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    return id;
  }

  GLuint texture(const std::string& path) {
    auto found = textures.find(path);
    if (found != textures.end()) return found->second;
    const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
    const GLuint id = image.empty() ? 0 : upload(image);
    textures[path] = id;
    return id;
  }
};

OffscreenRenderer::OffscreenRenderer(int width, int height)
    : gl_(std::make_unique<Gl>()), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 8192 || height > 8192) {
    throw RenderError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                      " out of range");
  }
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) throw RenderError("EGL has no eglGetPlatformDisplayEXT");
  gl_->display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (gl_->display == EGL_NO_DISPLAY || !eglInitialize(gl_->display, &major, &minor)) {
    throw RenderError("no EGL surfaceless display (is Mesa's libegl-mesa0 installed?)");
  }
  const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                      EGL_OPENGL_BIT, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8,
                                      EGL_BLUE_SIZE, 8, EGL_DEPTH_SIZE, 24, EGL_NONE};
  EGLConfig config;
  EGLint count = 0;
  if (!eglChooseConfig(gl_->display, config_attributes, &config, 1, &count) || count == 0) {
    throw RenderError("no EGL config for offscreen OpenGL");
  }
  eglBindAPI(EGL_OPENGL_API);
  gl_->context = eglCreateContext(gl_->display, config, EGL_NO_CONTEXT, nullptr);
  if (gl_->context == EGL_NO_CONTEXT) throw RenderError("cannot create an OpenGL context");
  gl_->make_current();

  glGenFramebuffers(1, &gl_->fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->fbo);
  glGenRenderbuffers(1, &gl_->color);
  glBindRenderbuffer(GL_RENDERBUFFER, gl_->color);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, gl_->color);
  glGenRenderbuffers(1, &gl_->depth);
  glBindRenderbuffer(GL_RENDERBUFFER, gl_->depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, gl_->depth);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError("the offscreen framebuffer is incomplete");
  }

  gl_->box = glGenLists(3);
  gl_->cylinder = gl_->box + 1;
  gl_->sphere = gl_->box + 2;
  glNewList(gl_->box, GL_COMPILE);
  unit_box();
  glEndList();
  glNewList(gl_->cylinder, GL_COMPILE);
  unit_cylinder();
  glEndList();
  glNewList(gl_->sphere, GL_COMPILE);
  unit_sphere();
  glEndList();
  cv::Mat floor(64, 64, CV_8UC3);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool light = ((x / 32) + (y / 32)) % 2 == 0;
      floor.at<cv::Vec3b>(y, x) = light ? cv::Vec3b(170, 180, 185) : cv::Vec3b(140, 150, 155);
    }
  }
  gl_->floor_texture = gl_->upload(floor);
}

OffscreenRenderer::~OffscreenRenderer() {
  if (gl_->context != EGL_NO_CONTEXT) {
    eglMakeCurrent(gl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(gl_->display, gl_->context);
  }
}

std::string OffscreenRenderer::gl_renderer() const {
  gl_->make_current();
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return name ? name : "?";
}

cv::Mat OffscreenRenderer::render(const Scene& scene, const Pose& camera,
                                  const CameraIntrinsics& in, cv::Mat* depth) {
  if (in.width != width_ || in.height != height_) {
    throw RenderError("this renderer draws " + std::to_string(width_) + "x" +
                      std::to_string(height_) + " images");
  }
  gl_->make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->fbo);
  glViewport(0, 0, width_, height_);
  glClearColor(0.72f, 0.8f, 0.9f, 1.0f);  // a pale sky
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_NORMALIZE);

  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  const double top = in.near_clip * std::tan(in.fov_y / 2);
  const double right = top * in.width / in.height;
  glFrustum(-right, right, -top, top, in.near_clip, in.far_clip);

  // The view: GL looks along -z with y up; our cameras look along x with z up.
  glMatrixMode(GL_MODELVIEW);
  Eigen::Matrix4d camera_to_world = Eigen::Matrix4d::Identity();
  camera_to_world.topLeftCorner<3, 3>() = camera.orientation.toRotationMatrix();
  camera_to_world.topRightCorner<3, 1>() = camera.position;
  Eigen::Matrix4d gl_to_camera = Eigen::Matrix4d::Zero();
  gl_to_camera(0, 2) = -1;  // GL -z -> camera x
  gl_to_camera(1, 0) = -1;  // GL x -> camera -y
  gl_to_camera(2, 1) = 1;   // GL y -> camera z
  gl_to_camera(3, 3) = 1;
  const Eigen::Matrix4d view = (camera_to_world * gl_to_camera).inverse();
  glLoadMatrixd(view.data());

  // Light: a sun from above, a fill light from the other side, and ambient.
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT0);
  glEnable(GL_LIGHT1);
  const GLfloat sun[] = {0.4f, 0.3f, 1.0f, 0.0f};
  const GLfloat fill[] = {-0.6f, -0.5f, 0.5f, 0.0f};
  const GLfloat diffuse[] = {0.65f, 0.65f, 0.62f, 1.0f};
  const GLfloat fill_diffuse[] = {0.35f, 0.35f, 0.37f, 1.0f};
  const GLfloat ambient[] = {0.35f, 0.35f, 0.37f, 1.0f};
  glLightfv(GL_LIGHT0, GL_POSITION, sun);
  glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
  glLightfv(GL_LIGHT1, GL_POSITION, fill);
  glLightfv(GL_LIGHT1, GL_DIFFUSE, fill_diffuse);
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
  glEnable(GL_COLOR_MATERIAL);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);

  // The floor: a 1 m checker over the scene's extent and beyond.
  glEnable(GL_TEXTURE_2D);
  glBindTexture(GL_TEXTURE_2D, gl_->floor_texture);
  glColor3f(1, 1, 1);
  const double extent = 30;
  glBegin(GL_QUADS);
  glNormal3f(0, 0, 1);
  glTexCoord2d(-extent / 2, -extent / 2);
  glVertex3d(-extent, -extent, 0);
  glTexCoord2d(extent / 2, -extent / 2);
  glVertex3d(extent, -extent, 0);
  glTexCoord2d(extent / 2, extent / 2);
  glVertex3d(extent, extent, 0);
  glTexCoord2d(-extent / 2, extent / 2);
  glVertex3d(-extent, extent, 0);
  glEnd();

  for (const ShapeView& s : scene.shapes) {
    const GLuint texture = s.texture.empty() ? 0 : gl_->texture(s.texture);
    if (texture) {
      glEnable(GL_TEXTURE_2D);
      glBindTexture(GL_TEXTURE_2D, texture);
    } else {
      glDisable(GL_TEXTURE_2D);
    }
    glColor4f(s.color[0], s.color[1], s.color[2], s.color[3]);
    glPushMatrix();
    double m[16];
    pose_matrix(s.pose, m);
    glMultMatrixd(m);
    switch (s.shape) {
      case Shape::Box:
        glScaled(s.size.x(), s.size.y(), s.size.z());
        glCallList(gl_->box);
        break;
      case Shape::Cylinder:
        glScaled(s.size.x(), s.size.x(), s.size.z());
        glCallList(gl_->cylinder);
        break;
      case Shape::Sphere:
        glScaled(s.size.x(), s.size.x(), s.size.x());
        glCallList(gl_->sphere);
        break;
    }
    glPopMatrix();
  }
  glDisable(GL_TEXTURE_2D);

  cv::Mat image(height_, width_, CV_8UC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_BGR, GL_UNSIGNED_BYTE, image.data);
  cv::flip(image, image, 0);
  if (depth) {
    cv::Mat window(height_, width_, CV_32F);
    glReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, window.data);
    cv::flip(window, window, 0);
    const float n = in.near_clip, f = in.far_clip;
    depth->create(height_, width_, CV_32F);
    for (int y = 0; y < height_; ++y) {
      const float* d = window.ptr<float>(y);
      float* z = depth->ptr<float>(y);
      for (int x = 0; x < width_; ++x) z[x] = 2 * n * f / (f + n - (2 * d[x] - 1) * (f - n));
    }
  }
  return image;
}

}  // namespace macsim::render
