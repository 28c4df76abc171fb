// Overview pictures over DDS (macsim --pictures DIR): a request gives a PNG of the named camera
// mode in DIR, also while paused in lock-step; names that are not plain file names and unknown
// modes are refused; new names stop at --max-pictures; without --pictures every request is
// refused, saying so.
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <opencv2/core.hpp>

#include "macsim/client/picture_client.h"
#include "macsim/images/image_files.h"
#include "support/child_process.h"
#include "support/test_domain.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace mm = macsim_msgs::msg::dds_;

TEST(Pictures, ARequestWritesThePngOfTheCameraModeEvenWhilePaused) {
  TempDir dir("macsim_pictures_");
  const int domain = unique_test_domain();
  ChildProcess macsim({bin("macsim"), "--world", source("worlds/DemoWorld_v1.xml"), "--domain",
                       std::to_string(domain), "--lockstep", "--cameras", "off", "--pictures",
                       dir.path() + "/out", "--snapshot-size", "320x200"});
  ASSERT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
  dds::Participant p({domain, "", "picture_test"});
  client::PictureClient pictures(p);
  const auto reply = pictures.take("overview", "Chase", 20s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->code(), mm::ERR_OK) << reply->message();
  EXPECT_EQ(reply->file(), dir.path() + "/out/overview.png");
  EXPECT_DOUBLE_EQ(reply->sim_time(), 0.0);  // never stepped
  const cv::Mat image = macsim::images::read_image(reply->file());
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.size(), cv::Size(320, 200));
  cv::Scalar mean, deviation;
  cv::meanStdDev(image, mean, deviation);
  EXPECT_GT(deviation[0] + deviation[1] + deviation[2], 20.0);  // a scene, not a blank

  for (const auto& [name, mode] : std::vector<std::pair<std::string, std::string>>{
           {"../escape", "Chase"}, {"", "Chase"}, {".hidden", "Chase"}, {"ok", "NoSuchMode"}}) {
    const auto refused = pictures.take(name, mode, 20s);
    ASSERT_TRUE(refused.has_value());
    EXPECT_EQ(refused->code(), mm::ERR_INVALID_ARGUMENT) << name << " " << mode;
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/escape.png"));
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0) << macsim.output();
}

TEST(Pictures, NewFileNamesStopAtTheCapANameUsedBeforeIsWrittenAgain) {
  TempDir dir("macsim_pictures_");
  const int domain = unique_test_domain();
  ChildProcess macsim({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                       std::to_string(domain), "--lockstep", "--cameras", "off", "--pictures",
                       dir.path(), "--snapshot-size", "64x48", "--max-pictures", "2"});
  ASSERT_TRUE(macsim.wait_for_output("stepping on request", 30s)) << macsim.output();
  dds::Participant p({domain, "", "picture_test"});
  client::PictureClient pictures(p);
  for (const char* name : {"a", "b"}) {
    const auto reply = pictures.take(name, "Follow", 20s);
    ASSERT_TRUE(reply.has_value());
    EXPECT_EQ(reply->code(), mm::ERR_OK) << reply->message();
  }
  const auto refused = pictures.take("c", "Follow", 20s);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->code(), mm::ERR_LIMIT_REACHED) << refused->message();
  EXPECT_NE(refused->message().find("--max-pictures"), std::string::npos) << refused->message();
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/c.png"));
  const auto again = pictures.take("a", "Chase", 20s);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->code(), mm::ERR_OK) << again->message();
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                          std::filesystem::directory_iterator()),
            2);
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0) << macsim.output();
}

TEST(Pictures, WithoutPicturesEveryRequestIsRefusedSayingSo) {
  const int domain = unique_test_domain();
  ChildProcess macsim({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                       std::to_string(domain), "--cameras", "off"});
  ASSERT_TRUE(macsim.wait_for_output("stepping at real-time factor", 30s)) << macsim.output();
  dds::Participant p({domain, "", "picture_test"});
  client::PictureClient pictures(p);
  const auto reply = pictures.take("overview", "Follow", 20s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->code(), mm::ERR_NOT_APPLICABLE);
  EXPECT_NE(reply->message().find("--pictures"), std::string::npos) << reply->message();
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0);
}

}  // namespace
}  // namespace macsim::test
