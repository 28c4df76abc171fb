// Image files through the codecs' module: not loaded until the first image is read or written,
// then PNG and BMP files and JPEG bytes round-trip; what cannot be read, decoded or written says
// so by an empty image or false, as OpenCV's own calls do.
#include "macsim/images/image_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>
#include <string>

#include "support/child_process.h"

namespace macsim::test {
namespace {

/// Whether this process has OpenCV's imgcodecs mapped (/proc/self/maps).
bool codecs_loaded() {
  std::ifstream maps("/proc/self/maps");
  std::stringstream text;
  text << maps.rdbuf();
  return text.str().find("libopencv_imgcodecs") != std::string::npos;
}

cv::Mat gradient(int rows, int cols) {
  cv::Mat image(rows, cols, CV_8UC3);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      image.at<cv::Vec3b>(r, c) = cv::Vec3b(uchar(4 * c), uchar(4 * r), uchar(100));
  return image;
}

// First in this file: ctest runs each test in a process of its own, and none before it here
// reads or writes an image.
TEST(ImageFiles, TheCodecsAreLoadedAtTheFirstImageOnly) {
  EXPECT_FALSE(codecs_loaded()) << "imgcodecs was mapped before any image file was touched";
  // The module beside this program is the build tree's lib/macsim/ one; naming it loads nothing.
  const std::string module = images::codecs_module_file();
  EXPECT_TRUE(std::filesystem::is_regular_file(module)) << module;
  EXPECT_NE(module.find("/lib/macsim/libmacsim_image_codecs.so"), std::string::npos) << module;
  EXPECT_FALSE(codecs_loaded());
  const TempDir dir("macsim_images_");
  ASSERT_TRUE(images::write_image(dir.path() + "/a.png", gradient(8, 8)));
  EXPECT_TRUE(codecs_loaded());
}

TEST(ImageFiles, PngAndBmpFilesComeBackPixelForPixel) {
  const TempDir dir("macsim_images_");
  const cv::Mat image = gradient(16, 24);
  for (const char* name : {"/g.png", "/g.bmp"}) {
    ASSERT_TRUE(images::write_image(dir.path() + name, image)) << name;
    const cv::Mat back = images::read_image(dir.path() + name);
    ASSERT_EQ(back.size(), image.size()) << name;
    ASSERT_EQ(back.type(), CV_8UC3) << name;
    EXPECT_EQ(cv::norm(back, image, cv::NORM_INF), 0.0) << name;
  }
}

TEST(ImageFiles, AsStoredKeepsAnAlphaChannelThatBgrDrops) {
  const TempDir dir("macsim_images_");
  cv::Mat rgba(4, 4, CV_8UC4, cv::Scalar(10, 20, 30, 128));
  ASSERT_TRUE(images::write_image(dir.path() + "/a.png", rgba));
  EXPECT_EQ(images::read_image(dir.path() + "/a.png", images::Pixels::AsStored).type(), CV_8UC4);
  EXPECT_EQ(images::read_image(dir.path() + "/a.png").type(), CV_8UC3);
}

TEST(ImageFiles, JpegBytesDecodeToTheImageWithinItsLoss) {
  const cv::Mat image(48, 64, CV_8UC3, cv::Scalar(10, 200, 30));
  const std::vector<unsigned char> jpeg = images::encode_jpeg(image, 90);
  ASSERT_GT(jpeg.size(), 100u);
  EXPECT_EQ(jpeg[0], 0xFF);
  EXPECT_EQ(jpeg[1], 0xD8);  // a JPEG file's start-of-image marker
  const cv::Mat back = images::decode_image(jpeg.data(), jpeg.size());
  ASSERT_EQ(back.size(), image.size());
  EXPECT_NEAR(back.at<cv::Vec3b>(20, 20)[1], 200, 4);
  // A lower quality makes fewer bytes of the same picture.
  EXPECT_LT(images::encode_jpeg(image, 10).size(), jpeg.size());
}

TEST(ImageFiles, WhatCannotBeReadDecodedOrWrittenSaysSo) {
  const TempDir dir("macsim_images_");
  EXPECT_TRUE(images::read_image(dir.path() + "/missing.png").empty());
  std::ofstream(dir.path() + "/text.png") << "not a PNG";
  EXPECT_TRUE(images::read_image(dir.path() + "/text.png").empty());
  const std::string garbage = "\x89PNG but nothing after";
  EXPECT_TRUE(images::decode_image(garbage.data(), garbage.size()).empty());
  EXPECT_TRUE(images::decode_image(garbage.data(), 0).empty());
  EXPECT_FALSE(images::write_image(dir.path() + "/no/such/folder/a.png", gradient(4, 4)));
  EXPECT_TRUE(images::encode_jpeg(cv::Mat(), 90).empty());
}

}  // namespace
}  // namespace macsim::test
