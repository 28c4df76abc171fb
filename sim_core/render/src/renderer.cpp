#include "macsim/render/renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "scene_drawer.h"

namespace macsim::render {

double CameraIntrinsics::focal() const { return height / 2.0 / std::tan(fov_y / 2); }

struct OffscreenRenderer::Gl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  GLuint fbo = 0, color = 0, depth = 0;
  std::unique_ptr<detail::SceneDrawer> drawer;

  void make_current() const {
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      throw RenderError("eglMakeCurrent failed");
    }
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

  gl_->drawer = std::make_unique<detail::SceneDrawer>();
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
  cv::Mat image;
  render_into(image, scene, camera, in, depth);
  return image;
}

void OffscreenRenderer::render_into(cv::Mat& image, const Scene& scene, const Pose& camera,
                                    const CameraIntrinsics& in, cv::Mat* depth) {
  if (in.width != width_ || in.height != height_) {
    throw RenderError("this renderer draws " + std::to_string(width_) + "x" +
                      std::to_string(height_) + " images");
  }
  gl_->make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->fbo);
  glViewport(0, 0, width_, height_);
  // Drawn with the image's rows top-down, so the pixels are read straight into the image.
  gl_->drawer->draw(scene, camera, in, detail::SceneDrawer::Rows::TopDown);

  if (image.u && image.u->refcount > 1) image.release();  // another holder keeps the old pixels
  image.create(height_, width_, CV_8UC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_BGR, GL_UNSIGNED_BYTE, image.data);
  if (depth) {
    cv::Mat window(height_, width_, CV_32F);
    glReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, window.data);
    const float n = in.near_clip, f = in.far_clip;
    depth->create(height_, width_, CV_32F);
    for (int y = 0; y < height_; ++y) {
      const float* d = window.ptr<float>(y);
      float* z = depth->ptr<float>(y);
      for (int x = 0; x < width_; ++x) z[x] = 2 * n * f / (f + n - (2 * d[x] - 1) * (f - n));
    }
  }
}

}  // namespace macsim::render
