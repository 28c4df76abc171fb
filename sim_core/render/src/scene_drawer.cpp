#include "scene_drawer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "macsim/images/image_files.h"

namespace macsim::render::detail {

namespace {

constexpr int kSegments = 24;

void unit_box() {
  // The cube [-0.5, 0.5]^3, one quad a face with its normal and texture coordinates.
  static const float faces[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                    {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
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

SceneDrawer::SceneDrawer() {
  box_ = glGenLists(3);
  cylinder_ = box_ + 1;
  sphere_ = box_ + 2;
  glNewList(box_, GL_COMPILE);
  unit_box();
  glEndList();
  glNewList(cylinder_, GL_COMPILE);
  unit_cylinder();
  glEndList();
  glNewList(sphere_, GL_COMPILE);
  unit_sphere();
  glEndList();
  cv::Mat floor(64, 64, CV_8UC3);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool light = ((x / 32) + (y / 32)) % 2 == 0;
      floor.at<cv::Vec3b>(y, x) = light ? cv::Vec3b(170, 180, 185) : cv::Vec3b(140, 150, 155);
    }
  }
  floor_texture_ = upload(floor);
}

unsigned SceneDrawer::upload(const cv::Mat& bgr) {
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

unsigned SceneDrawer::texture(const std::string& path) {
  auto found = textures_.find(path);
  if (found != textures_.end()) {
    found->second.drawn = draws_;
    return found->second.id;
  }
  // Checked when the world took it; looked at again, as it may have changed since: a regular
  // file of a texture's size only (a FIFO would block the renderer).
  constexpr std::uintmax_t kMaxTextureFileBytes = std::uintmax_t(16) << 20;
  std::error_code error;
  const bool readable = std::filesystem::is_regular_file(path, error) &&
                        std::filesystem::file_size(path, error) <= kMaxTextureFileBytes && !error;
  const cv::Mat image = readable ? images::read_image(path) : cv::Mat();
  const unsigned id = image.empty() ? 0 : upload(image);
  const std::size_t bytes = image.empty() ? 0 : image.total() * image.elemSize();
  textures_[path] = {id, bytes, draws_};
  texture_bytes_ += bytes;
  return id;
}

void SceneDrawer::trim_textures() {
  while (textures_.size() > kMaxTextures || texture_bytes_ > kMaxTextureBytes) {
    auto oldest = textures_.end();
    for (auto t = textures_.begin(); t != textures_.end(); ++t) {
      if (t->second.drawn < draws_ &&
          (oldest == textures_.end() || t->second.drawn < oldest->second.drawn)) {
        oldest = t;
      }
    }
    if (oldest == textures_.end()) return;  // all in the scene just drawn: kept until later
    if (oldest->second.id != 0) {
      const GLuint id = oldest->second.id;
      glDeleteTextures(1, &id);
    }
    texture_bytes_ -= oldest->second.bytes;
    textures_.erase(oldest);
  }
}

void SceneDrawer::draw(const Scene& scene, const Pose& camera, const CameraIntrinsics& intrinsics,
                       Rows rows) {
  ++draws_;
  glClearColor(0.72f, 0.8f, 0.9f, 1.0f);  // a pale sky
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_NORMALIZE);
  // Every shape is closed and wound counter-clockwise seen from outside: faces turned away
  // from the camera are never seen, and not rasterising them halves the pixels shaded.
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  // Top-down rows mirror the image vertically, which turns every face's winding over.
  glFrontFace(rows == Rows::TopDown ? GL_CW : GL_CCW);

  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  if (rows == Rows::TopDown) glScaled(1, -1, 1);
  const double top = intrinsics.near_clip * std::tan(intrinsics.fov_y / 2);
  const double right = top * intrinsics.width / intrinsics.height;
  glFrustum(-right, right, -top, top, intrinsics.near_clip, intrinsics.far_clip);

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

  for (const ShapeView& s : scene.shapes) {
    const GLuint image = s.texture.empty() ? 0 : texture(s.texture);
    if (image) {
      glEnable(GL_TEXTURE_2D);
      glBindTexture(GL_TEXTURE_2D, image);
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
        glCallList(box_);
        break;
      case Shape::Cylinder:
        glScaled(s.size.x(), s.size.x(), s.size.z());
        glCallList(cylinder_);
        break;
      case Shape::Sphere:
        glScaled(s.size.x(), s.size.x(), s.size.x());
        glCallList(sphere_);
        break;
    }
    glPopMatrix();
  }
  // The floor last: a 1 m checker over the scene's extent and beyond. Where objects stand in
  // front of it the depth test drops its pixels before they are shaded.
  glEnable(GL_TEXTURE_2D);
  glBindTexture(GL_TEXTURE_2D, floor_texture_);
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
  glDisable(GL_TEXTURE_2D);
  trim_textures();
}

}  // namespace macsim::render::detail
