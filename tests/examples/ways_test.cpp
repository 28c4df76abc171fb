// kurt_navigate's parts: what it counts as driven through and around.
#include "ways.h"

#include <gtest/gtest.h>

#include <cmath>

#include "macsim/affordances/perception.h"

namespace kurt_navigate {
namespace {

namespace af = macsim::affordances;
const double kFloor = -af::SensorMount{}.base_height;  // the floor's z in base_link

TEST(NavigateWays, ThingsOnThePathAreDrivenThroughAndThoseBesideItAround) {
  Sightings s;
  macsim::client::Cloud cloud;
  auto thing = [&](double x, double y) {
    for (double dx = -0.05; dx <= 0.05; dx += 0.02)
      for (double dy = -0.05; dy <= 0.05; dy += 0.02)
        cloud.points.push_back({float(x + dx), float(y + dy), float(kFloor + 0.1)});
  };
  thing(1.0, 0.0);  // on the way
  thing(1.5, 0.6);  // beside it
  thing(2.0, 1.8);  // far off
  for (double y = -2.0; y <= 2.0; y += 0.05)
    cloud.points.push_back({2.9f, float(y), float(kFloor + 0.2)});  // a wall: not a thing
  // Taken facing +y from (1.5, -0.5): the point (x, y) is at (y + 0.5, 1.5 - x) in base_link.
  const macsim::affordances::Pose2 at{1.5, -0.5, M_PI / 2};
  macsim::client::Cloud turned;
  for (const auto& q : cloud.points) turned.points.push_back({q[1] + 0.5f, 1.5f - q[0], q[2]});
  s.add(turned, at);
  for (double x = 0; x <= 3.0; x += 0.05) s.pass({x, 0, 0});
  const auto counts = s.count(0.22);
  EXPECT_EQ(counts.seen, 3);
  EXPECT_EQ(counts.through, 1);
  EXPECT_EQ(counts.around, 1);
}

}  // namespace
}  // namespace kurt_navigate

