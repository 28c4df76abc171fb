// Layouts by seed: the same seed gives the same layout, another seed another; everything stays
// in its area and keeps its clearance; look-alikes share a colour from the palette; a world
// that cannot vary (no <VARIATION>, too crowded, a bad element) says why and where.
#include "macsim/sim_core/world_variation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "macsim/sim_core/world_loader.h"
#include "support/world_helpers.h"

namespace macsim::test {
namespace {

std::vector<const ObjectSpec*> cans(const WorldSpec& spec) {
  std::vector<const ObjectSpec*> out;
  for (const auto& o : spec.objects) {
    if (o.user_data == "can") out.push_back(&o);
  }
  return out;
}

TEST(WorldVariation, TheSameSeedGivesTheSameLayoutAndAnotherSeedAnother) {
  WorldSpec a = shipped_world("DemoWorld_v1.xml");
  WorldSpec b = shipped_world("DemoWorld_v1.xml");
  WorldSpec c = shipped_world("DemoWorld_v1.xml");
  const auto moved = vary_world(a, 5);
  EXPECT_EQ(moved.size(), 6u);  // the robot and five cans
  EXPECT_EQ(vary_world(b, 5), moved);
  EXPECT_NE(vary_world(c, 6), moved);
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_TRUE(a.objects[i].pose.position.isApprox(b.objects[i].pose.position));
  }
}

TEST(WorldVariation, EverythingStaysInItsAreaClearOfTheRestAndLookAlikesShareAColour) {
  for (uint32_t seed = 0; seed < 30; ++seed) {
    WorldSpec spec = shipped_world("DemoWorld_v1.xml");
    const WorldSpec original = spec;
    vary_world(spec, seed);
    const VariationSpec& v = *spec.variation;
    const auto placed = cans(spec);
    ASSERT_EQ(placed.size(), 5u);
    std::map<std::string, Color> colour_of_material;
    for (const ObjectSpec* can : placed) {
      const Eigen::Vector3d& p = can->pose.position;
      EXPECT_GE(p.x(), v.area[0]);
      EXPECT_LE(p.x(), v.area[2]);
      EXPECT_GE(p.y(), v.area[1]);
      EXPECT_LE(p.y(), v.area[3]);
      EXPECT_DOUBLE_EQ(p.z(), original.object(can->name)->pose.position.z());  // on the floor
      for (const ObjectSpec* other : placed) {
        if (other == can) continue;
        EXPECT_GE((other->pose.position - p).head<2>().norm(), v.clearance);
      }
      for (const auto& o : spec.objects) {
        if (o.user_data == "can" || o.kind != ObjectKind::Object) continue;
        EXPECT_GE((o.pose.position - p).head<2>().norm(), v.clearance) << seed << " " << o.name;
      }
      EXPECT_GE((spec.robots[0].pose.position - p).head<2>().norm(), v.clearance + 0.35);
      // One colour per material, from the palette.
      const Color colour = can->components.front().color;
      EXPECT_NE(std::find(v.colors.begin(), v.colors.end(), colour), v.colors.end());
      const auto [it, fresh] = colour_of_material.try_emplace(can->material, colour);
      EXPECT_EQ(it->second, colour) << can->name;
    }
    EXPECT_EQ(colour_of_material.size(), 3u);  // tin, lead, plastic
    const auto& robot = spec.robots[0].pose.position;
    EXPECT_GE(robot.x(), (*v.robot_area)[0]);
    EXPECT_LE(robot.x(), (*v.robot_area)[2]);
    // The variation built a world ODE accepts.
    EXPECT_NO_THROW(World world(spec));
  }
}

TEST(WorldVariation, AMaterialThatKeepsItsColourKeepsItInEveryLayout) {
  // DemoWorld_figure11: the lead cans blue in every layout, the tin cans one palette colour per
  // layout and never blue, so a colour means the same weight across layouts.
  const Color blue{0.1f, 0.2f, 0.9f, 1.0f};
  std::set<Color> tin_colours;
  for (uint32_t seed = 1; seed <= 20; ++seed) {
    WorldSpec spec = shipped_world("DemoWorld_figure11.xml");
    ASSERT_EQ(spec.variation->keep_colors, std::vector<std::string>{"lead"});
    vary_world(spec, seed);
    int heavy = 0;
    for (const ObjectSpec* can : cans(spec)) {
      const Color& c = can->components.front().color;
      EXPECT_TRUE(can->magnetizable) << can->name;
      if (can->material == "lead") {
        ++heavy;
        EXPECT_EQ(c, blue) << seed << " " << can->name;
      } else {
        EXPECT_EQ(can->material, "tin");
        EXPECT_NE(c, blue) << seed << " " << can->name;
        EXPECT_NE(std::find(spec.variation->colors.begin(), spec.variation->colors.end(), c),
                  spec.variation->colors.end());
        tin_colours.insert(c);
      }
    }
    EXPECT_EQ(heavy, 3);
  }
  EXPECT_GE(tin_colours.size(), 3u);  // the light cans' colour does vary
}

/// The floor of a world seen from above on a 4 cm grid: what stands on each cell, and whether
/// a robot of a given half width can get from one point to another between it.
class FloorMap {
 public:
  static constexpr double kCell = 0.04;
  FloorMap(double x0, double y0, double x1, double y1)
      : x0_(x0), y0_(y0), columns_(static_cast<int>((x1 - x0) / kCell)),
        rows_(static_cast<int>((y1 - y0) / kCell)),
        blocked_(static_cast<std::size_t>(columns_ * rows_), 0) {}

  /// Marks the cells under every component of `object` taller than 1 cm; with
  /// `without_traversable`, not those a robot drives over or pushes away (a whole portable
  /// object, or a part no higher than 6 cm).
  void add(const ObjectSpec& object, bool without_traversable) {
    for (const auto& c : object.components) {
      const Pose pose = object.pose * c.pose;
      const Eigen::Vector3d axis = pose.orientation * Eigen::Vector3d::UnitZ();
      const bool upright = std::fabs(axis.z()) > 0.99;
      Eigen::Vector3d half;  // the component's box in its own frame
      if (c.shape == Shape::Box)
        half = c.size / 2;
      else if (c.shape == Shape::Cylinder)
        half = {c.size[0], c.size[0], c.size[2] / 2};
      else
        half = Eigen::Vector3d::Constant(c.size[0]);
      // Its corners on the floor; its top.
      std::vector<Eigen::Vector2d> corners;
      double top = -1e9;
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner((k & 1 ? 1 : -1) * half.x(), (k & 2 ? 1 : -1) * half.y(),
                                     (k & 4 ? 1 : -1) * half.z());
        const Eigen::Vector3d at = pose.position + pose.orientation * corner;
        top = std::max(top, at.z());
        corners.push_back(at.head<2>());
      }
      if (c.shape == Shape::Sphere) top = pose.position.z() + c.size[0];
      if (top < 0.01) continue;  // a mark on the floor
      if (without_traversable && (object.portable || top <= 0.06)) continue;
      // Round things standing (or any sphere) cover a disc; the rest the hull of their corners.
      const bool disc = c.shape == Shape::Sphere || (c.shape == Shape::Cylinder && upright);
      const Eigen::Vector2d centre = pose.position.head<2>();
      const auto hull = convex_hull(corners);
      double xa = 1e9, xb = -1e9, ya = 1e9, yb = -1e9;
      for (const auto& q : corners) {
        xa = std::min(xa, q.x()), xb = std::max(xb, q.x());
        ya = std::min(ya, q.y()), yb = std::max(yb, q.y());
      }
      for (int i = std::max(0, column(xa)); i <= std::min(columns_ - 1, column(xb)); ++i) {
        for (int j = std::max(0, row(ya)); j <= std::min(rows_ - 1, row(yb)); ++j) {
          const Eigen::Vector2d p(x0_ + (i + 0.5) * kCell, y0_ + (j + 0.5) * kCell);
          const bool under = disc ? (p - centre).norm() <= c.size[0] + kCell / 2
                                  : inside(hull, p, kCell / 2);
          if (under) blocked_[index(i, j)] = 1;
        }
      }
    }
  }

  /// Whether a disc of `radius` gets from `from` to `to` without touching what was added.
  bool connected(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double radius) const {
    // Distance to the nearest blocked cell (8-neighbour chamfer, 3 per side, 4 per diagonal),
    // then a flood fill through the cells far enough from everything.
    const int far = 1 << 20;
    std::vector<int> d(blocked_.size());
    for (std::size_t k = 0; k < d.size(); ++k) d[k] = blocked_[k] ? 0 : far;
    auto at = [&](int i, int j) {
      return i < 0 || i >= columns_ || j < 0 || j >= rows_ ? far : d[index(i, j)];
    };
    for (int j = 0; j < rows_; ++j) {
      for (int i = 0; i < columns_; ++i) {
        int& v = d[index(i, j)];
        v = std::min({v, at(i - 1, j) + 3, at(i, j - 1) + 3, at(i - 1, j - 1) + 4,
                      at(i + 1, j - 1) + 4});
      }
    }
    for (int j = rows_ - 1; j >= 0; --j) {
      for (int i = columns_ - 1; i >= 0; --i) {
        int& v = d[index(i, j)];
        v = std::min({v, at(i + 1, j) + 3, at(i, j + 1) + 3, at(i + 1, j + 1) + 4,
                      at(i - 1, j + 1) + 4});
      }
    }
    const int clear = static_cast<int>(std::ceil(3 * radius / kCell));
    std::vector<char> seen(blocked_.size(), 0);
    std::vector<std::pair<int, int>> todo{{column(from.x()), row(from.y())}};
    const std::pair<int, int> goal{column(to.x()), row(to.y())};
    while (!todo.empty()) {
      const auto [i, j] = todo.back();
      todo.pop_back();
      if (i < 0 || i >= columns_ || j < 0 || j >= rows_) continue;
      const std::size_t k = index(i, j);
      if (seen[k] || d[k] < clear) continue;
      seen[k] = 1;
      if (std::pair{i, j} == goal) return true;
      todo.insert(todo.end(), {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}});
    }
    return false;
  }

 private:
  /// The convex hull of points, counter-clockwise (Andrew's monotone chain).
  static std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
    std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) {
      return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    });
    auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
    };
    std::vector<Eigen::Vector2d> hull(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 1e-12) --k;
      hull[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
      while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 1e-12) --k;
      hull[k++] = p[i];
    }
    hull.resize(k > 1 ? k - 1 : k);
    return hull;
  }
  /// Whether `p` lies in the convex polygon `hull` grown by `margin`.
  static bool inside(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p,
                     double margin) {
    for (std::size_t i = 0; i < hull.size(); ++i) {
      const Eigen::Vector2d a = hull[i], b = hull[(i + 1) % hull.size()];
      const Eigen::Vector2d edge = b - a;
      const double length = edge.norm();
      if (length < 1e-12) continue;
      // Outward distance (counter-clockwise: the outside is to the right of each edge).
      const double out = (edge.x() * (p - a).y() - edge.y() * (p - a).x()) / -length;
      if (out > margin) return false;
    }
    return true;
  }
  int column(double x) const { return static_cast<int>(std::floor((x - x0_) / kCell)); }
  int row(double y) const { return static_cast<int>(std::floor((y - y0_) / kCell)); }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j * columns_ + i); }
  double x0_, y0_;
  int columns_, rows_;
  std::vector<char> blocked_;
};

TEST(WorldVariation, TheClutterFieldLeavesNoWayAroundInAThirdOfItsLayouts) {
  // The KURT3D (0.44 m over its tracks) from its start to the goal 6 m ahead: with everything
  // an obstacle, a third of the layouts or more have no way through; driving over and pushing
  // what the trials call traversable (portable things, parts of 6 cm or less), nearly all do.
  constexpr double kHalfWidth = 0.22;
  const Eigen::Vector2d start(0, 0), goal(6, 0);
  int closed = 0, open_by_traversing = 0;
  std::string layouts;
  for (uint32_t seed = 1; seed <= 50; ++seed) {
    WorldSpec spec = shipped_world("clutter_field.xml");
    vary_world(spec, seed);
    ASSERT_EQ(spec.robots.front().pose.position.head<2>(), start) << "the start does not vary";
    FloorMap all(-1.2, -2.2, 7.7, 2.2), solid(-1.2, -2.2, 7.7, 2.2);
    for (const auto& o : spec.objects) {
      all.add(o, false);
      solid.add(o, true);
    }
    const bool around = all.connected(start, goal, kHalfWidth);
    const bool through = solid.connected(start, goal, kHalfWidth);
    closed += around ? 0 : 1;
    open_by_traversing += through ? 1 : 0;
    layouts += std::to_string(seed) + (around ? "" : "-closed") + (through ? "" : "-blocked") + " ";
  }
  std::printf("clutter_field seeds 1-50: %d with no way around, %d with a way by traversing\n",
              closed, open_by_traversing);
  EXPECT_GE(closed, 17) << layouts;
  EXPECT_GE(open_by_traversing, 45) << layouts;
}

TEST(WorldVariation, AJointsMotorForceIsDrawnPerSeedWithinItsRangeAndLeavesThePlacesAsTheyWere) {
  std::set<double> drawn;
  for (uint32_t seed = 1; seed <= 20; ++seed) {
    WorldSpec stiff = shipped_world("goals/stiff_switch.xml");
    WorldSpec plain = shipped_world("goals/demonstrator.xml");
    const auto moved = vary_world(stiff, seed);
    const auto placed = vary_world(plain, seed);
    // The force is drawn after every place: the layouts are the demonstrator's.
    ASSERT_EQ(moved.size(), placed.size() + 1);
    EXPECT_TRUE(std::equal(placed.begin(), placed.end(), moved.begin()));
    const auto joint = std::find_if(stiff.joints.begin(), stiff.joints.end(), [](const JointSpec& j) {
      return j.name == "doors/door_00/switch_component/BUTTON_SLIDER";
    });
    ASSERT_NE(joint, stiff.joints.end());
    EXPECT_GE(joint->max_force, 1.0);
    EXPECT_LE(joint->max_force, 1.4);
    drawn.insert(joint->max_force);
    WorldSpec again = shipped_world("goals/stiff_switch.xml");
    vary_world(again, seed);
    for (const auto& j : again.joints)
      if (j.name == joint->name) EXPECT_EQ(j.max_force, joint->max_force);
  }
  EXPECT_EQ(drawn.size(), 20u);

  const std::string no_joint =
      "<WORLD>\n<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,3,3</AREA>\n"
      "<VARY_JOINT><JOINT>SLIDER</JOINT><MAX_FORCE>1,2</MAX_FORCE></VARY_JOINT></VARIATION>\n"
      "</WORLD>";
  WorldSpec spec = load_world_string(no_joint, "no_joint.xml");
  try {
    vary_world(spec, 1);
    ADD_FAILURE() << "a range for a joint the world does not have";
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("no joint's name ends with 'SLIDER'"), std::string::npos) << e.what();
  }
  for (const char* bad : {"<MAX_FORCE>2,1</MAX_FORCE>", "<MAX_FORCE>-1,1</MAX_FORCE>", "<MAX_FORCE>1</MAX_FORCE>",
                          "<MAX_FORCE>nan,1</MAX_FORCE>", "<MAX_FORCE>1,1e308</MAX_FORCE>", ""}) {
    const std::string text = std::string("<WORLD>\n<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,3,3</AREA>\n") +
                             "<VARY_JOINT><JOINT>S</JOINT>" + bad + "</VARY_JOINT></VARIATION></WORLD>";
    try {
      load_world_string(text, "bad.xml");
      ADD_FAILURE() << bad;
    } catch (const WorldFileError& e) {
      EXPECT_EQ(e.line(), 3) << bad << ": " << e.what();
    }
  }
}

TEST(WorldVariation, AWorldThatCannotVarySaysWhyAndWhere) {
  WorldSpec plain = load_world_string("<WORLD><ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT></WORLD>",
                                      "plain.xml");
  EXPECT_THROW(vary_world(plain, 1), WorldFileError);

  const std::string crowded =
      "<WORLD>\n<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,0.3,0.3</AREA><CLEARANCE>0.4</CLEARANCE>"
      "</VARIATION>\n"
      "<OBJECT><ID>a</ID><SHAPE>SPHERE</SHAPE><RADIUS>0.05</RADIUS><USER_DATA>can</USER_DATA></OBJECT>"
      "<OBJECT><ID>b</ID><SHAPE>SPHERE</SHAPE><RADIUS>0.05</RADIUS><USER_DATA>can</USER_DATA></OBJECT>"
      "</WORLD>";
  WorldSpec spec = load_world_string(crowded, "crowded.xml");
  try {
    vary_world(spec, 1);
    ADD_FAILURE() << "two objects 0.5 m apart in a 0.3 m square";
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("no room for object 'b'"), std::string::npos) << e.what();
  }

  std::string many = "<WORLD><VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,100,100</AREA></VARIATION>";
  for (int i = 0; i < 1001; ++i) {
    many += "<OBJECT><ID>c" + std::to_string(i) +
            "</ID><SHAPE>SPHERE</SHAPE><RADIUS>0.05</RADIUS><USER_DATA>can</USER_DATA></OBJECT>";
  }
  WorldSpec crowd = load_world_string(many + "</WORLD>", "many.xml");
  try {
    vary_world(crowd, 1);
    ADD_FAILURE() << "1001 objects placed";
  } catch (const WorldFileError& e) {
    EXPECT_NE(std::string(e.what()).find("at most 1000"), std::string::npos) << e.what();
  }

  for (const char* bad : {"<VARIATION><AREA>0,0,1,1</AREA></VARIATION>",
                          "<VARIATION><OBJECTS>can</OBJECTS><AREA>1,0,0,1</AREA></VARIATION>",
                          "<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,1</AREA></VARIATION>",
                          "<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,1,nan</AREA></VARIATION>",
                          "<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,1,1e300</AREA></VARIATION>",
                          "<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,1,1</AREA>"
                          "<COLOR>2,0,0</COLOR></VARIATION>",
                          "<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,1,1</AREA>"
                          "<KEEP_COLOR></KEEP_COLOR></VARIATION>"}) {
    EXPECT_THROW(load_world_string(std::string("<WORLD>") + bad + "</WORLD>", "bad.xml"),
                 WorldFileError)
        << bad;
  }
}

}  // namespace
}  // namespace macsim::test
