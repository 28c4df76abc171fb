// The client's decoding of sensor messages: images to BGR cv::Mat, PointCloud2 to points;
// what does not add up gives nothing rather than garbage.
#include "macsim/client/robot_devices.h"

#include <gtest/gtest.h>

#include <cstring>

namespace macsim::client {
namespace {

namespace sm = sensor_msgs::msg::dds_;

sm::Image_ image(const std::string& encoding, int channels, int width, int height) {
  sm::Image_ msg;
  msg.encoding(encoding);
  msg.width(width);
  msg.height(height);
  msg.step(width * channels);
  msg.data().assign(static_cast<std::size_t>(width) * height * channels, 0);
  return msg;
}

TEST(RobotDevices, ImagesBecomeBgrMatsAndBrokenOnesNothing) {
  sm::Image_ rgb = image("rgb8", 3, 4, 2);
  rgb.data()[0] = 200;  // red in the first pixel
  const cv::Mat bgr = to_bgr(rgb);
  ASSERT_EQ(bgr.size(), cv::Size(4, 2));
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 200));
  sm::Image_ mono = image("mono8", 1, 3, 3);
  mono.data()[4] = 77;
  EXPECT_EQ(to_bgr(mono).at<cv::Vec3b>(1, 1), cv::Vec3b(77, 77, 77));
  EXPECT_EQ(to_bgr(image("bgr8", 3, 5, 5)).type(), CV_8UC3);

  sm::Image_ short_data = image("bgr8", 3, 4, 4);
  short_data.data().resize(10);
  EXPECT_TRUE(to_bgr(short_data).empty());
  EXPECT_TRUE(to_bgr(image("yuv422", 2, 4, 4)).empty());
  sm::Image_ bad_step = image("bgr8", 3, 4, 4);
  bad_step.step(2);
  EXPECT_TRUE(to_bgr(bad_step).empty());
}

sm::PointCloud2_ cloud(const std::vector<std::array<float, 3>>& points, uint32_t step = 16) {
  sm::PointCloud2_ msg;
  for (const auto& [name, offset] : std::vector<std::pair<const char*, uint32_t>>{{"x", 0}, {"y", 4}, {"z", 8}}) {
    sm::PointField_ f;
    f.name(name);
    f.offset(offset);
    f.datatype(7);
    f.count(1);
    msg.fields().push_back(f);
  }
  msg.height(1);
  msg.width(points.size());
  msg.point_step(step);
  msg.data().assign(points.size() * step, 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::memcpy(msg.data().data() + i * step, points[i].data(), 12);
  }
  return msg;
}

TEST(RobotDevices, CloudsDecodeTheirXyzFieldsWhateverThePointStep) {
  const auto decoded = to_cloud(cloud({{1, 2, 3}, {-4, 5.5f, 0}}));
  ASSERT_EQ(decoded.points.size(), 2u);
  EXPECT_EQ(decoded.points[1], (std::array<float, 3>{-4, 5.5f, 0}));

  auto truncated = cloud({{1, 2, 3}, {4, 5, 6}});
  truncated.data().resize(20);
  EXPECT_TRUE(to_cloud(truncated).points.empty());
  auto no_z = cloud({{1, 2, 3}});
  no_z.fields().pop_back();
  EXPECT_TRUE(to_cloud(no_z).points.empty());
  auto doubles = cloud({{1, 2, 3}});
  doubles.fields()[0].datatype(8);  // FLOAT64: not what this reads
  EXPECT_TRUE(to_cloud(doubles).points.empty());
}

}  // namespace
}  // namespace macsim::client
