// The picture server's caps without DDS: pictures in flight (each holds a captured scene) and
// distinct files written per run.
#include "pictures/picture_admission.h"

#include <gtest/gtest.h>

namespace macsim {
namespace {

TEST(PictureAdmission, PicturesInFlightAreCappedAndAnAnswerFreesAPlace) {
  PictureAdmission admission(2, 100);
  EXPECT_FALSE(admission.admit("a"));
  EXPECT_FALSE(admission.admit("b"));
  const auto busy = admission.admit("c");
  ASSERT_TRUE(busy);
  EXPECT_NE(busy->find("busy"), std::string::npos) << *busy;
  EXPECT_NE(busy->find("2"), std::string::npos) << *busy;
  EXPECT_EQ(admission.in_flight(), 2u);
  EXPECT_EQ(admission.files(), 2u);  // the refused name took no place
  admission.done();
  EXPECT_FALSE(admission.admit("c"));
}

TEST(PictureAdmission, DistinctFilesAreCappedANameUsedBeforeIsAlwaysTaken) {
  PictureAdmission admission(100, 2);
  EXPECT_FALSE(admission.admit("a"));
  EXPECT_FALSE(admission.admit("b"));
  const auto full = admission.admit("c");
  ASSERT_TRUE(full);
  EXPECT_NE(full->find("--max-pictures"), std::string::npos) << *full;
  EXPECT_NE(full->find("'c'"), std::string::npos) << *full;
  EXPECT_FALSE(admission.admit("a"));  // written over
  EXPECT_EQ(admission.files(), 2u);
}

}  // namespace
}  // namespace macsim
