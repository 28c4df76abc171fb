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
#include "support/floor_map.h"
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

/// A world whose <VARIATION> holds `inner` on its third line is refused, naming that line.
void expect_refused_on_line_3(const std::string& inner) {
  const std::string text = "<WORLD>\n<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,3,3</AREA>\n" + inner +
                           "</VARIATION></WORLD>";
  try {
    load_world_string(text, "bad.xml");
    ADD_FAILURE() << inner;
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 3) << inner << ": " << e.what();
  }
}

/// A world whose <VARIATION> holds `inner` on its third line loads, and varying it is refused
/// naming that line and saying `says`.
void expect_variation_refused_on_line_3(const std::string& inner, const std::string& says) {
  WorldSpec spec = load_world_string(
      "<WORLD>\n<VARIATION><OBJECTS>can</OBJECTS><AREA>0,0,3,3</AREA>\n" + inner + "</VARIATION></WORLD>", "v.xml");
  try {
    vary_world(spec, 1);
    ADD_FAILURE() << inner;
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 3) << e.what();
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
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
    for (const auto& j : again.joints) {
      if (j.name == joint->name) {
        EXPECT_EQ(j.max_force, joint->max_force);
      }
    }
  }
  EXPECT_EQ(drawn.size(), 20u);

  expect_variation_refused_on_line_3("<VARY_JOINT><JOINT>SLIDER</JOINT><MAX_FORCE>1,2</MAX_FORCE></VARY_JOINT>",
                                     "no joint's name ends with 'SLIDER'");
  for (const char* bad : {"<MAX_FORCE>2,1</MAX_FORCE>", "<MAX_FORCE>-1,1</MAX_FORCE>", "<MAX_FORCE>1</MAX_FORCE>",
                          "<MAX_FORCE>nan,1</MAX_FORCE>", "<MAX_FORCE>1,1e308</MAX_FORCE>", ""})
    expect_refused_on_line_3(std::string("<VARY_JOINT><JOINT>S</JOINT>") + bad + "</VARY_JOINT>");
}

TEST(WorldVariation, APlaceGroupPutsItsObjectsWhollyInItsOwnAreaAfterEverythingElse) {
  for (uint32_t seed = 1; seed <= 10; ++seed) {
    WorldSpec cluttered = shipped_world("goals/cluttered_way.xml");
    const auto moved = vary_world(cluttered, seed);
    ASSERT_EQ(cluttered.variation->groups.size(), 1u);
    const Eigen::Vector4d area = cluttered.variation->groups.front().area;
    int placed = 0;
    for (const auto& o : cluttered.objects) {
      if (o.user_data != "clutter") continue;
      ++placed;
      const double r = footprint_radius(o);
      const Eigen::Vector2d at = o.pose.position.head<2>();
      EXPECT_GE(at.x() - r, area[0] - 1e-9) << o.name;
      EXPECT_GE(at.y() - r, area[1] - 1e-9) << o.name;
      EXPECT_LE(at.x() + r, area[2] + 1e-9) << o.name;
      EXPECT_LE(at.y() + r, area[3] + 1e-9) << o.name;
      for (const auto& other : cluttered.objects) {
        if (&other == &o || (other.kind != ObjectKind::Object && other.kind != ObjectKind::SwitchBase)) continue;
        EXPECT_GE((other.pose.position.head<2>() - at).norm(), r + footprint_radius(other) + 0.05 - 1e-9)
            << o.name << " and " << other.name << ", seed " << seed;
      }
    }
    EXPECT_EQ(placed, 10);
    // The clutter is placed last: the lines before it are those of the cans and the robot.
    EXPECT_EQ(moved.size(), 1u + 5u + 10u);
    EXPECT_NE(moved.back().find("environment_01/"), std::string::npos) << moved.back();
  }
  for (const char* bad : {"<PLACE><AREA>0,0,1,1</AREA></PLACE>", "<PLACE><OBJECTS>x</OBJECTS></PLACE>",
                          "<PLACE><OBJECTS>x</OBJECTS><AREA>0,0,1,inf</AREA></PLACE>",
                          "<PLACE><OBJECTS>x</OBJECTS><AREA>0,0,1,1</AREA><CLEARANCE>-1</CLEARANCE></PLACE>"})
    expect_refused_on_line_3(bad);
  expect_variation_refused_on_line_3("<PLACE><OBJECTS>logs</OBJECTS><AREA>0,0,1,1</AREA></PLACE>",
                                     "no object has the user data 'logs'");
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
