// dynamicObjectTest N: the seed's supervisor examples (Table 2) as a DDS client. Each test
// prints what it does and checks every effect on the world state topic; exit 1 if an effect
// is not seen.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "macsim/client/supervisor_client.h"
#include "macsim/client/world_state.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/convert.h"
#include "macsim/dds/data_files.h"
#include "macsim/dds/log.h"

namespace mm = macsim_msgs::msg::dds_;
using macsim::client::SupervisorClient;
namespace supervisor = macsim::client::supervisor;
using macsim::client::WorldStateClient;
using Objects = WorldStateClient::Objects;

namespace {

struct Context {
  SupervisorClient& supervisor;
  WorldStateClient& world;
  std::string textures;  // a folder of BMP textures the simulator can read
  int failures = 0;
};

/// Calls an operation and reports it; returns the reply (code checked by the caller).
mm::SupervisorReply_ call(Context& c, const std::string& what, const SupervisorClient::Request& r) {
  const auto reply = c.supervisor.call(r);
  if (!reply) {
    std::printf("  %-48s no reply: %s\n", what.c_str(),
                macsim::client::describe(c.supervisor.last_outcome(), "supervisor").c_str());
    ++c.failures;
    return {};
  }
  std::printf("  %-48s %s%s\n", what.c_str(),
              reply->code() == mm::ERR_OK ? "ok" : "error: ", reply->message().c_str());
  return *reply;
}

/// Waits for an effect on the world state; reports and counts it.
void expect(Context& c, const std::string& effect,
            const std::function<bool(const Objects&, const std::set<uint32_t>&)>& check) {
  const bool seen = c.world.wait(check, std::chrono::seconds(10));
  std::printf("    %s %s\n", seen ? "seen:" : "NOT SEEN:", effect.c_str());
  if (!seen) ++c.failures;
}

const mm::Object_* find(const Objects& objects, uint32_t id) {
  auto it = objects.find(id);
  return it == objects.end() ? nullptr : &it->second.object();
}

double z_of(const Objects& o, uint32_t id) {
  auto* x = find(o, id);
  return x ? x->pose().position().z() : -1;
}

SupervisorClient::Request create(int shape, std::array<double, 3> size, std::array<double, 3> at,
                                 bool portable, const std::string& user_data) {
  mm::Object_ object;
  mm::Component_ c;
  c.shape(shape);
  c.size(size);
  c.pose().orientation().w(1.0);
  c.color({0.6f, 0.6f, 0.6f, 1.0f});
  object.components().push_back(c);
  object.portable(portable);
  object.user_data(user_data);
  object.pose().position(macsim::dds::point(at[0], at[1], at[2]));
  object.pose().orientation().w(1.0);
  return supervisor::create_object(object);
}

void create_and_destroy(Context& c) {
  std::printf("TestObjectCreateAndDestroy: create, relocate, recolour and destroy objects\n");
  std::vector<uint32_t> ids;
  ids.push_back(
      call(c, "create a portable box", create(0, {0.2, 0.2, 0.2}, {-0.5, 0.3, 0.5}, true, "demo"))
          .object_id());
  ids.push_back(call(c, "create a portable cylinder",
                     create(1, {0.05, 0, 0.2}, {-0.5, -0.5, 0.5}, true, "demo"))
                    .object_id());
  ids.push_back(
      call(c, "create a portable sphere", create(2, {0.08, 0, 0}, {-1.5, 0.3, 0.5}, true, "demo"))
          .object_id());
  ids.push_back(
      call(c, "create a fixed box", create(0, {0.3, 0.3, 0.3}, {-2.5, -1.5, 0.15}, false, "demo"))
          .object_id());
  expect(c, "the four objects appear; the box lands on the floor (z 0.1)",
         [&](const Objects& o, const auto&) {
           return find(o, ids[0]) && find(o, ids[1]) && find(o, ids[2]) && find(o, ids[3]) &&
                  std::fabs(z_of(o, ids[0]) - 0.1) < 0.005;
         });
  call(c, "move the box to (-0.5, 0.9)", supervisor::set_position(ids[0], {-0.5, 0.9, 0.1}));
  call(c, "paint the sphere blue", supervisor::set_color(ids[2], {0.1f, 0.2f, 0.9f, 1}));
  expect(c, "the box is at y 0.9 and the sphere is blue", [&](const Objects& o, const auto&) {
    return find(o, ids[0]) && std::fabs(find(o, ids[0])->pose().position().y() - 0.9) < 0.01 &&
           find(o, ids[2]) && find(o, ids[2])->components()[0].color()[2] > 0.85f;
  });
  call(c, "destroy the objects with user data 'demo'", supervisor::destroy_by_user_data("demo"));
  expect(c, "all four are gone (disposed)", [&](const Objects& o, const std::set<uint32_t>& gone) {
    for (uint32_t id : ids) {
      if (find(o, id) || !gone.count(id)) return false;
    }
    return true;
  });
}

void change_properties(Context& c) {
  std::printf("TestChangeObjectProperties: a clean floor, new objects, changed and pushed\n");
  // Portable ones: walls and doors stay.
  call(c, "destroy all portable objects", supervisor::destroy_all(mm::DESTROY_PORTABLE_OBJECTS));
  expect(c, "no portable object is left", [](const Objects& o, const auto&) {
    for (const auto& [id, s] : o) {
      if (s.object().portable()) return false;
    }
    return true;
  });
  const uint32_t box =
      call(c, "create a box", create(0, {0.1, 0.1, 0.1}, {-1.0, 0.0, 0.3}, true, "")).object_id();
  const uint32_t ball =
      call(c, "create a ball", create(2, {0.1, 0, 0}, {-1.0, 1.0, 0.3}, true, "")).object_id();
  call(c, "resize the box to 0.3 m", supervisor::set_box_size(box, 0, {0.3, 0.3, 0.3}));
  call(c, "turn the box by 45 degrees",
       supervisor::set_orientation(box, {0, 0, std::sin(M_PI / 8), std::cos(M_PI / 8)}));
  expect(c, "the box is 0.3 m large and rests at z 0.15", [&](const Objects& o, const auto&) {
    auto* b = find(o, box);
    return b && b->components()[0].size()[0] == 0.3 && std::fabs(z_of(o, box) - 0.15) < 0.005;
  });
  call(c, "push the ball with 200 N along +x", supervisor::add_force(ball, {200, 0, 0}));
  expect(c, "the ball rolls away along +x", [&](const Objects& o, const auto&) {
    auto* b = find(o, ball);
    return b && b->pose().position().x() > -0.8;
  });
}

void composites(Context& c) {
  std::printf("TestCompositeObjects: move, recolour, retexture and resize composites\n");
  uint32_t can = 0;
  c.world.wait([&](const Objects& o, const auto&) {
    for (const auto& [id, s] : o) {  // a can if there is one, else any portable composite
      const bool composite = s.object().portable() && s.object().components().size() > 1;
      if (composite && (can == 0 || s.object().name().find("can") != std::string::npos)) can = id;
    }
    return can != 0;
  });
  if (!can) {
    std::printf("  no portable composite in this world\n");
    ++c.failures;
    return;
  }
  const Objects now = c.world.objects();
  std::printf("  composite: %s\n", find(now, can)->name().c_str());
  call(c, "move it to (-0.5, 0.3)", supervisor::set_position(can, {-0.5, 0.3, 0.01}));
  expect(c, "moved", [&](const Objects& o, const auto&) {
    auto* x = find(o, can);
    return x && std::fabs(x->pose().position().x() + 0.5) < 0.02 &&
           std::fabs(x->pose().position().y() - 0.3) < 0.02;
  });
  call(c, "paint it green", supervisor::set_color(can, {0.1f, 0.8f, 0.1f, 1}));
  call(c, "give its first component the checker texture",
       supervisor::set_texture(can, c.textures + "/checker.bmp", 0));
  const double height = find(now, can)->components()[0].size()[2];
  call(c, "widen its cylinder (the shape is not kept)",
       supervisor::set_cylinder_size(can, 0, 0.06, height, true));
  expect(c, "green, textured, its cylinder 0.06 m in radius", [&](const Objects& o, const auto&) {
    auto* x = find(o, can);
    return x && x->components()[1].color()[1] > 0.7f &&
           x->components()[0].texture().find("checker.bmp") != std::string::npos &&
           x->components()[0].size()[0] == 0.06;
  });
}

void ramps(Context& c) {
  std::printf(
      "TestRampFunctions: relocate, recolour, retexture ramps and print their dimensions\n");
  std::vector<uint32_t> found;
  c.world.wait([&](const Objects& o, const auto&) {
    found.clear();
    for (const auto& [id, s] : o) {
      if (s.object().kind() == mm::KIND_RAMP) found.push_back(id);
    }
    return !found.empty();
  });
  if (found.empty()) {
    std::printf("  no ramp in this world\n");
    ++c.failures;
    return;
  }
  for (uint32_t ramp : found) {
    const Objects before = c.world.objects();
    const double x = find(before, ramp)->pose().position().x();
    const double y = find(before, ramp)->pose().position().y();
    call(c, "move it 0.3 m along x", supervisor::set_position(ramp, {x + 0.3, y, 0}));
    call(c, "paint it orange", supervisor::set_color(ramp, {0.9f, 0.5f, 0.1f, 1}));
    call(c, "give it the wood texture", supervisor::set_texture(ramp, c.textures + "/wood.bmp"));
    expect(c, "moved, orange, wooden", [&](const Objects& o, const auto&) {
      auto* r = find(o, ramp);
      return r && std::fabs(r->pose().position().x() - (x + 0.3)) < 1e-6 &&
             r->components()[0].color()[1] < 0.6f &&
             r->components()[0].texture().find("wood.bmp") != std::string::npos;
    });
    const Objects now = c.world.objects();
    const auto* r = find(now, ramp);
    const double width = r->ramp()[0], height = r->ramp()[1], angle = r->ramp()[2];
    std::printf("  %s: width %.3f m, height %.3f m, depth %.3f m, angle %.1f deg\n",
                r->name().c_str(), width, height, height / std::tan(angle), angle * 180 / M_PI);
  }
}

}  // namespace

int main(int argc, char** argv) {
  macsim::dds::ParticipantOptions participant{0, "", "dynamicObjectTest"};
  std::string textures = macsim::dds::data_file("worlds/DemoEnvironment_v1/textures");
  macsim::dds::CommandLine cli(
      "dynamicObjectTest",
      "usage: dynamicObjectTest N (1 create and destroy, 2 change object properties, 3 composite "
      "objects, 4 ramp functions), against a running macsim (e.g. on worlds/DemoWorld_v1.xml).\n"
      "Exit 0: every effect seen; 1: some effect not seen; 2: usage, or no simulator.");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.option("textures", "DIR",
             "folder of BMP textures (default: the installed worlds' DemoEnvironment_v1/textures)",
             &textures);
  // The seed's form: the test number as an argument of its own (not an option's value: every
  // option here but --help takes one).
  int test = 0;
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const bool option_value =
        i > 1 && argv[i - 1][0] == '-' && std::string(argv[i - 1]) != "--help";
    if (test == 0 && !option_value &&
        std::string(argv[i]).find_first_not_of("0123456789") == std::string::npos) {
      test = std::atoi(argv[i]);
    } else {
      rest.push_back(argv[i]);
    }
  }
  if (auto code = cli.parse(static_cast<int>(rest.size()), rest.data())) return *code;
  if (test < 1 || test > 4) {
    macsim::log::error("dynamicObjectTest: give the test number 1 to 4 (see --help)");
    return 2;
  }
  try {
    macsim::dds::Participant dds(participant);
    SupervisorClient supervisor(dds);
    WorldStateClient world(dds);
    if (!supervisor.wait_for_server(std::chrono::seconds(15))) {
      macsim::log::error("dynamicObjectTest: no simulator on DDS domain {}", participant.domain);
      return 2;
    }
    Context c{supervisor, world, std::filesystem::absolute(textures).string()};
    switch (test) {
      case 1:
        create_and_destroy(c);
        break;
      case 2:
        change_properties(c);
        break;
      case 3:
        composites(c);
        break;
      case 4:
        ramps(c);
        break;
    }
    std::printf(
        "dynamicObjectTest %d: %s\n", test,
        c.failures == 0 ? "every effect seen" : (std::to_string(c.failures) + " failed").c_str());
    return c.failures == 0 ? 0 : 1;
  } catch (const macsim::dds::DdsError& e) {
    macsim::log::error("dynamicObjectTest: DDS error: {}", e.what());
    return 2;
  }
}
