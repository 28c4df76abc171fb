// The programs' command lines, run as a user would: help, bad input, validation, signals.
#include <dirent.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/core.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "macsim/dds/participant.h"
#include "macsim/images/image_files.h"
#include "support/child_process.h"
#include "support/test_domain.h"
#include "topic_graph.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;

TEST(MacsimCli, EveryProgramsHelpListsTheCommonOptions) {
  for (const char* program : {"macsim", "helloKurt", "interfaceTest", "dynamicObjectTest",
                              "kurt_demo", "kurt_navigate", "kurt_adapter", "kurt_emulator",
                              "bench_dds", "affordance_trials", "macsim_topic", "macsim_web"}) {
    ChildProcess p({bin(program), "--help"});
    ASSERT_EQ(p.wait_for_exit(10s), 0) << program;
    EXPECT_NE(p.output().find("--domain N"), std::string::npos) << program << ": " << p.output();
    EXPECT_NE(p.output().find("usage"), std::string::npos) << program << ": " << p.output();
  }
}

TEST(MacsimCli, BenchmarksRefuseBadArgumentsWithoutAborting) {
  if (!std::filesystem::exists(bin("bench_world"))) GTEST_SKIP() << "benchmarks not built";
  struct Case {
    std::vector<std::string> argv;
    int code;
    const char* says;
  };
  for (const Case& c : std::vector<Case>{
           {{bin("bench_world"), "--help"}, 0, "usage: bench_world"},
           {{bin("bench_world"), "--bogus"}, 2, "unknown option '--bogus'"},
           {{bin("bench_world"), "/nonexistent/world.xml"}, 1, "no such world file"},
           {{bin("bench_robot"), "-h"}, 0, "usage: bench_robot"},
           {{bin("bench_step_rate")}, 2, "usage: bench_step_rate"},
           {{bin("bench_step_rate"), source("worlds/small_room.xml"), "abc"}, 2, "SIM_SECONDS"},
           {{bin("bench_demo"), "--help"},
            0,
            "bench_demo [--domain N] [--world FILE] [--affordances DIR] [SEEDS [FIRST]]"},
           {{bin("bench_demo"), "0"}, 2, "SEEDS must be positive"},
           {{bin("bench_demo"), "--domain", "200"}, 2, "--domain takes the first of the 80"},
           {{bin("bench_navigate"), "--help"},
            0,
            "usage: bench_navigate [--domain N] [--policy model|avoid]"},
           {{bin("bench_navigate"), "--domain", "x7", "--affordances", "x"}, 2, "0-152, not 'x7'"},
           {{bin("bench_navigate"), "5"}, 2, "--affordances DIR is required"},
           {{bin("bench_navigate"), "--policy", "random", "--affordances", "x"},
            2,
            "--policy is model or avoid, not 'random'"},
           {{bin("bench_affordances"), "--help"}, 0, "usage: bench_affordances [TRIALS]"},
           {{bin("bench_affordances"), "0"}, 2, "TRIALS must be positive"},
           {{bin("bench_peers"), "--help"}, 0, "usage: bench_peers"},
           {{bin("bench_peers"), "--scene", "nope"}, 2, "unknown scene 'nope'"},
           {{bin("bench_peers"), "--repeats", "0"}, 2, "bad argument"},
           {{bin("bench_peers"), "--repeats", "5x"}, 2, "bad argument '5x'"},
           {{bin("bench_peers"), "--engine", "bullet"}, 2, "unknown engine 'bullet'"},
           {{bin("bench_models"), "--help"}, 0, "usage: bench_models"},
           {{bin("bench_models"), "5x"}, 2, "PREDICTIONS must be positive, not '5x'"},
           {{bin("bench_planning"), "--help"}, 0, "usage: bench_planning"},
           {{bin("bench_planning"), "0"}, 2, "RUNS must be positive, not '0'"},
           {{bin("bench_startup"), "--help"}, 0, "usage: bench_startup"},
           {{bin("bench_startup"), "0"}, 2, "STARTS must be positive, not '0'"},
           {{bin("bench_client"), "--help"}, 0, "usage: bench_client"},
           {{bin("bench_client")}, 2, "--domain"}}) {
    ChildProcess p(c.argv);
    EXPECT_EQ(p.wait_for_exit(20s), c.code) << c.argv.back() << ": " << p.output();
    EXPECT_NE(p.output().find(c.says), std::string::npos) << p.output();
  }
}

// The peers benchmark compares engines only if they simulate the same scene: the vehicle must
// drive as commanded and a pile must come to rest where it should in raw ODE, sim_core and
// MuJoCo alike (a wrong MJCF or baseline would show here).
TEST(MacsimCli, BenchPeersEnginesAgreeOnTheVehicleAndAPile) {
  std::map<std::string, double> figures;
  for (const char* scene : {"vehicle", "pile_10"}) {
    ChildProcess p({bin("bench_peers"), "--scene", scene, "--repeats", "1"});
    ASSERT_EQ(p.wait_for_exit(60s), 0) << p.output();
    std::istringstream lines(p.output());
    std::string name;
    double value;
    while (lines >> name >> value) {
      figures[name] = value;
      lines.ignore(1 << 20, '\n');
    }
  }
  for (const char* engine : {"raw_ode", "sim_core", "mujoco"}) {
    const std::string vehicle = std::string("fidelity.vehicle.") + engine;
    ASSERT_TRUE(figures.count(vehicle + ".robot_travel")) << engine;
    EXPECT_NEAR(figures[vehicle + ".robot_travel"], 1.5, 0.03) << engine;
    EXPECT_NEAR(figures[vehicle + ".robot_yaw_change"], 0.0, 1.0) << engine;
    const std::string pile = std::string("fidelity.pile_10.") + engine;
    ASSERT_TRUE(figures.count(pile + ".rest_pose_error_max")) << engine;
    EXPECT_LT(figures[pile + ".rest_pose_error_max"], 0.003) << engine;
    EXPECT_LT(figures[pile + ".kinetic_energy_end"], 1e-6) << engine;
    EXPECT_GT(figures[std::string("step_rate.pile_10.") + engine], 0.0) << engine;
  }
}

TEST(MacsimCli, SeedVariesTheLayoutTheSameWayEachTime) {
  auto layout = [](const std::string& world, const std::string& seed, int code) {
    ChildProcess p({bin("macsim"), "--world", source(world), "--seed", seed, "--validate"});
    EXPECT_EQ(p.wait_for_exit(20s), code) << seed << ": " << p.output();
    return p.output();
  };
  const std::string seven = layout("worlds/DemoWorld_v1.xml", "7", 0);
  EXPECT_NE(seven.find("layout of seed 7"), std::string::npos) << seven;
  EXPECT_NE(seven.find("robot kurt at"), std::string::npos) << seven;
  EXPECT_NE(seven.find("environment_00/can_heavy_01 at"), std::string::npos) << seven;
  EXPECT_EQ(layout("worlds/DemoWorld_v1.xml", "7", 0), seven);
  const std::string eight = layout("worlds/DemoWorld_v1.xml", "8", 0);
  EXPECT_NE(eight.substr(eight.find("layout")), seven.substr(seven.find("layout")));
  EXPECT_NE(layout("worlds/small_room.xml", "7", 1).find("has no <VARIATION>"), std::string::npos);
  EXPECT_NE(layout("worlds/DemoWorld_v1.xml", "-2", 2).find("--seed must be 0 or more"),
            std::string::npos);
}

TEST(MacsimCli, InteropProgramsNeverActOnHelpABadArgumentOrDomainZero) {
  for (const char* program : {"cyclone_listen", "cyclone_drive"}) {
    ChildProcess help({bin(program), "--help"});
    EXPECT_EQ(help.wait_for_exit(3s), 0) << program;
    EXPECT_NE(help.output().find("usage"), std::string::npos) << help.output();
    for (const char* bad : {"--bogus", "0", "12abc", "999"}) {
      ChildProcess p({bin(program), bad});
      EXPECT_EQ(p.wait_for_exit(3s), 2) << program << " " << bad << ": " << p.output();
    }
  }
}

/// The programs in build/bin.
std::vector<std::string> built_programs() {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(bin(""))) {
    if (entry.is_regular_file() && access(entry.path().c_str(), X_OK) == 0) {
      names.push_back(entry.path().filename().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(MacsimCli, NoProgramActsOnHelpABadArgumentOrWithoutADomain) {
  // Discovery on the default domain 0 (no test uses it) and on this test's own: a program that
  // acted would show a writer there.
  const int domain = unique_test_domain();
  topic::TopicGraph on_zero, on_domain;
  dds::Participant zero({0, "", "watch_domain_zero", &on_zero});
  dds::Participant mine({domain, "", "watch_test_domain", &on_domain});
  const auto programs = built_programs();
  ASSERT_GE(programs.size(), 25u);
  const std::string d = std::to_string(domain);
  for (const std::string& program : programs) {
    for (const auto& [args, code] : std::vector<std::pair<std::vector<std::string>, int>>{
             {{"--help"}, 0},
             {{"--bogus-argument"}, 2},
             {{"--bogus-argument", "--domain", d}, 2},
             {{"--domain", d, "--bogus-argument"}, 2}}) {
      std::vector<std::string> argv{bin(program)};
      argv.insert(argv.end(), args.begin(), args.end());
      ChildProcess p(argv);
      EXPECT_EQ(p.wait_for_exit(10s), code) << program << " " << args.front() << ": " << p.output();
      if (code == 0) {
        EXPECT_TRUE(p.output().find("usage") != std::string::npos ||
                    p.output().find("--gtest_filter") != std::string::npos)
            << program << ": " << p.output();
      }
    }
  }
  // Those that move a robot or change a simulation do nothing without --domain.
  for (const std::vector<std::string>& bare :
       {std::vector<std::string>{"helloKurt"},
        {"interfaceTest", "-load", "worlds/ramps.xml"},
        {"dynamicObjectTest", "1"},
        {"kurt_demo"},
        {"kurt_navigate", "--policy", "avoid"},
        {"kurt_adapter", "--can", "udp:47801:47802"},
        {"cyclone_drive"},
        {"cyclone_listen"},
        {"affordance_trials", "--trials", "1", "--out", ::testing::TempDir() + "never.csv"},
        {"macsim_topic", "pub", "/kurt/cmd_vel", "geometry_msgs/msg/Twist", "{linear: {x: 1}}"},
        {"macsim_topic", "play", "/tmp"}}) {
    std::vector<std::string> argv = bare;
    argv[0] = bin(argv[0]);
    ChildProcess p(argv);
    EXPECT_EQ(p.wait_for_exit(10s), 2) << bare[0] << ": " << p.output();
    std::string said = p.output();
    std::transform(said.begin(), said.end(), said.begin(), ::tolower);
    EXPECT_NE(said.find("domain"), std::string::npos) << bare[0] << ": " << p.output();
  }
  std::this_thread::sleep_for(1s);
  for (const auto* graph : {&on_zero, &on_domain}) {
    for (const auto& [name, t] : graph->topics()) {
      EXPECT_TRUE(t.writers.empty()) << name << " got a writer from " << t.writers[0].participant;
    }
  }
}

// OpenCV's imgcodecs loads about 130 libraries (GDAL, Poppler, HDF5...) at a process's start,
// 0.2 s of CPU: no program links it, only the codecs' module that a program loads when it first
// reads or writes an image file (idl/images).
TEST(MacsimCli, OnlyTheImageCodecsModuleLinksOpenCvsImageCodecs) {
  const auto dynamic_section = [](const std::string& file) {
    ChildProcess p({"/usr/bin/readelf", "--dynamic", file});
    EXPECT_EQ(p.wait_for_exit(20s), 0) << file << ": " << p.output();
    return p.output();
  };
  int elf_programs = 0;
  for (const std::string& program : built_programs()) {
    char magic[4] = {};
    std::ifstream(bin(program), std::ios::binary).read(magic, sizeof magic);
    if (std::string(magic, sizeof magic) != "\x7f" "ELF") continue;  // a script
    ++elf_programs;
    const std::string dynamic = dynamic_section(bin(program));
    EXPECT_EQ(dynamic.find("libopencv_imgcodecs"), std::string::npos) << program << ": " << dynamic;
  }
  EXPECT_GE(elf_programs, 25);
  const std::string module = dynamic_section(bin("../lib/macsim/libmacsim_image_codecs.so"));
  EXPECT_NE(module.find("libopencv_imgcodecs"), std::string::npos) << module;
}

TEST(MacsimCli, TestBinariesAnswerHelpAndRefuseAnUnknownArgumentInsteadOfRunningTheirSuite) {
  for (const char* program :
       {"sim_core_tests", "dds_bridge_tests", "idl_tests", "kurt_adapter_tests", "render_tests",
        "examples_tests", "asan_tests", "affordance_tests", "affordances_tests", "topic_tests",
        "process_tests",
        "integration_tests"}) {
    ChildProcess p({bin(program), "--bogus"});
    EXPECT_EQ(p.wait_for_exit(10s), 2) << program << ": " << p.output();
    EXPECT_NE(p.output().find("unknown argument '--bogus'"), std::string::npos) << p.output();
    EXPECT_EQ(p.output().find("[ RUN      ]"), std::string::npos) << program;
    ChildProcess help({bin(program), "--help"});
    EXPECT_EQ(help.wait_for_exit(3s), 0) << program << ": " << help.output();
    EXPECT_NE(help.output().find("--gtest_filter"), std::string::npos) << help.output();
    EXPECT_EQ(help.output().find("[ RUN      ]"), std::string::npos) << program;
  }
}

TEST(MacsimCli, TheWorldLimitsCanBeLoweredAndRaised) {
  const std::string world = source("worlds/DemoWorld_v1.xml");
  ChildProcess low({bin("macsim"), "--world", world, "--validate", "--max-objects", "10"});
  EXPECT_EQ(low.wait_for_exit(20s), 1) << low.output();
  EXPECT_NE(low.output().find("a world holds at most 10 objects"), std::string::npos)
      << low.output();
  ChildProcess shallow({bin("macsim"), "--world", world, "--validate", "--max-import-depth", "1"});
  EXPECT_EQ(shallow.wait_for_exit(20s), 1) << shallow.output();
  EXPECT_NE(shallow.output().find("imports nest at most 1 deep"), std::string::npos)
      << shallow.output();
  ChildProcess high({bin("macsim"), "--world", world, "--validate", "--max-objects", "200000"});
  EXPECT_EQ(high.wait_for_exit(20s), 0) << high.output();
  ChildProcess zero({bin("macsim"), "--world", world, "--validate", "--max-objects", "0"});
  EXPECT_EQ(zero.wait_for_exit(20s), 2) << zero.output();
}

TEST(MacsimCli, MalformedWorldExitsNonZeroNamingFileAndLine) {
  const std::string path = ::testing::TempDir() + "malformed_world.xml";
  std::ofstream(path)
      << "<WORLD>\n  <ROBOT>\n    <ID>kurt</ID>\n  </ROBOT>\n  <OBJECT>\n</WORLD>\n";
  ChildProcess p(
      {bin("macsim"), "--world", path, "--domain", std::to_string(unique_test_domain())});
  const auto code = p.wait_for_exit(20s);
  ASSERT_TRUE(code.has_value());
  EXPECT_NE(*code, 0);
  EXPECT_NE(p.output().find(path + ":5: malformed XML: element not closed by its end tag <OBJECT>"),
            std::string::npos)
      << p.output();
  EXPECT_NE(p.output().find("malformed XML"), std::string::npos) << p.output();
}

TEST(MacsimCli, BadNumberInWorldNamesItsLine) {
  const std::string path = ::testing::TempDir() + "bad_number_world.xml";
  std::ofstream(path) << "<WORLD>\n<PHYSICS>\n<STEP>0.001</STEP>\n<GRAVITY>0,0,down</GRAVITY>\n"
                         "</PHYSICS>\n</WORLD>\n";
  ChildProcess p({bin("macsim"), "--world", path});
  EXPECT_EQ(p.wait_for_exit(20s), 1);
  EXPECT_NE(p.output().find(path + ":4: <GRAVITY>"), std::string::npos) << p.output();
}

TEST(MacsimCli, UsageErrorsExitTwo) {
  {
    ChildProcess p({bin("macsim")});
    EXPECT_EQ(p.wait_for_exit(10s), 2);
    EXPECT_NE(p.output().find("--world FILE is required"), std::string::npos) << p.output();
  }
  {
    ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain", "300"});
    EXPECT_EQ(p.wait_for_exit(10s), 2);
    EXPECT_NE(p.output().find("--domain"), std::string::npos) << p.output();
  }
  for (const char* cameras : {"off", "64x48"}) {  // the camera schedule runs either way
    for (const char* rate : {"0", "-5", "inf"}) {
      ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                      std::to_string(unique_test_domain()), "--cameras", cameras, "--camera-rate",
                      rate});
      EXPECT_EQ(p.wait_for_exit(20s), 2) << p.output();
      EXPECT_NE(p.output().find("--camera-rate"), std::string::npos) << p.output();
    }
  }
  {
    ChildProcess p({bin("helloKurt"), "--speed", "fast"});
    EXPECT_EQ(p.wait_for_exit(10s), 2);
    EXPECT_NE(p.output().find("bad value 'fast' for --speed"), std::string::npos) << p.output();
  }
}

TEST(MacsimCli, ValidatePrintsASummaryAndExitsZero) {
  ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--validate"});
  ASSERT_EQ(p.wait_for_exit(20s), 0) << p.output();
  EXPECT_NE(p.output().find(
                "4 objects (3 portable, 1 fixed; 4 objects), 0 doors, 1 robots [kurt: kurt3d]"),
            std::string::npos)
      << p.output();
}

// Objects that start inside each other: named with file, line and depth by --validate (exit 0),
// refused by --strict with the exit code of a bad world file; shipped worlds are clean. By
// default the deeply tangled ones are moved apart on load, each named; --keep-overlaps keeps
// them where the file puts them.
TEST(MacsimCli, ValidateNamesObjectsThatStartInsideEachOtherAndStrictRefusesThem) {
  const std::string world = source("tests/worlds/overlapping_objects.xml");
  ChildProcess parted({bin("macsim"), "--world", world, "--validate"});
  ASSERT_EQ(parted.wait_for_exit(20s), 0) << parted.output();
  for (const std::string& line :
       {world + ":14: warning: 'box_a' started 0.100 m deep inside 'box_b': moved ",
        world + ":18: warning: 'box_b' started 0.100 m deep inside 'box_a': moved ",
        world + ":22: warning: 'box_in_kurt' started 0.155 m deep inside 'kurt': moved ",
        world + ":26: warning: 'sunk_ball' and 'ground' start inside each other, 0.050 m deep",
        std::string("macsim: 1 pair of objects start inside each other (warnings above)")}) {
    EXPECT_NE(parted.output().find(line), std::string::npos) << line << "\n" << parted.output();
  }
  EXPECT_EQ(parted.output().find("'kurt' started"), std::string::npos) << parted.output();

  ChildProcess validate({bin("macsim"), "--world", world, "--validate", "--keep-overlaps"});
  ASSERT_EQ(validate.wait_for_exit(20s), 0) << validate.output();
  const std::string out = validate.output();
  for (const std::string& line :
       {world + ":14: warning: 'box_a' and 'box_b' start inside each other, 0.100 m deep",
        world + ":22: warning: 'box_in_kurt' and 'kurt' start inside each other, 0.155 m deep",
        world + ":26: warning: 'sunk_ball' and 'ground' start inside each other, 0.050 m deep",
        std::string("macsim: 3 pairs of objects start inside each other (warnings above)")}) {
    EXPECT_NE(out.find(line), std::string::npos) << line << "\n" << out;
  }
  for (const char* touching : {"floor_box", "can_on_box", "box_at_wall"}) {
    EXPECT_EQ(out.find(touching), std::string::npos) << touching << "\n" << out;
  }

  ChildProcess strict({bin("macsim"), "--world", world, "--validate", "--strict"});
  ASSERT_EQ(strict.wait_for_exit(20s), 1) << strict.output();
  EXPECT_NE(strict.output().find("macsim: " + world +
                                 ":22: refused: 3 pairs of objects start inside each other: "
                                 "'box_in_kurt' and 'kurt' 0.155 m deep; 'box_a' and 'box_b'"),
            std::string::npos)
      << strict.output();
  // Not only when validating: macsim refuses to serve it.
  ChildProcess serve({bin("macsim"), "--world", world, "--strict", "--cameras", "off", "--domain",
                      std::to_string(unique_test_domain())});
  ASSERT_EQ(serve.wait_for_exit(20s), 1) << serve.output();
  EXPECT_EQ(serve.output().find("serving on DDS"), std::string::npos) << serve.output();

  for (const char* shipped : {"worlds/DemoWorld_v1.xml", "worlds/small_room.xml"}) {
    ChildProcess clean({bin("macsim"), "--world", source(shipped), "--validate", "--strict"});
    ASSERT_EQ(clean.wait_for_exit(20s), 0) << clean.output();
    EXPECT_NE(clean.output().find("macsim: no objects start inside each other"), std::string::npos)
        << clean.output();
    EXPECT_EQ(clean.output().find("warning"), std::string::npos) << clean.output();
  }
}

TEST(MacsimCli, OverlapWarningsAreCappedWithACountOfTheRest) {
  const std::string path = ::testing::TempDir() + "boxes_at_one_point.xml";
  {
    std::ofstream file(path);
    file << "<WORLD><NAME>pile</NAME>\n";
    for (int i = 0; i < 30; ++i) {
      file << "<OBJECT><ID>box_" << i << "</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE>"
           << "<DIMS>0.2,0.2,0.2</DIMS><POS>0,0,0.1</POS></OBJECT>\n";
    }
    file << "</WORLD>\n";
  }
  ChildProcess p({bin("macsim"), "--world", path, "--validate", "--keep-overlaps"});
  ASSERT_EQ(p.wait_for_exit(20s), 0) << p.output();
  std::istringstream lines(p.output());
  int named = 0;
  for (std::string line; std::getline(lines, line);) {
    named += line.find("' start inside each other, 0.200 m deep") != std::string::npos;
  }
  EXPECT_EQ(named, 20) << p.output();  // of 435 pairs
  EXPECT_NE(p.output().find("warning: ... and 415 more pairs of objects inside each other"),
            std::string::npos)
      << p.output();
  EXPECT_NE(p.output().find("macsim: 435 pairs of objects start inside each other"),
            std::string::npos)
      << p.output();
  // Loaded as macsim loads by default, the heap is spread: 20 lines and a count of the rest.
  ChildProcess parted({bin("macsim"), "--world", path, "--validate"});
  ASSERT_EQ(parted.wait_for_exit(20s), 0) << parted.output();
  EXPECT_NE(parted.output().find(" more objects or robots moved apart"), std::string::npos)
      << parted.output();
  EXPECT_NE(parted.output().find("macsim: no objects start inside each other"), std::string::npos)
      << parted.output();
}

// A world a request loads is checked too: its pairs are warned of in macsim's log and, under
// --strict, the load is refused with the same message while the old world runs on.
TEST(MacsimCli, StrictRefusesARequestToLoadAWorldWhoseObjectsStartInsideEachOther) {
  const std::string domain = std::to_string(unique_test_domain());
  ChildProcess macsim({bin("macsim"), "--world", source("tests/worlds/DemoWorld_stiff_switch.xml"),
                       "--strict", "--domain", domain, "--cameras", "off"});
  ASSERT_TRUE(macsim.wait_for_output("stepping", 30s)) << macsim.output();
  const std::string world = source("tests/worlds/overlapping_objects.xml");
  ChildProcess load({bin("interfaceTest"), "-load", world, "--domain", domain});
  EXPECT_EQ(load.wait_for_exit(60s), 1) << load.output();
  EXPECT_NE(load.output().find(world + ":22: refused: 3 pairs of objects start inside each other"),
            std::string::npos)
      << load.output();
  EXPECT_TRUE(macsim.wait_for_output("'box_a' and 'box_b' start inside each other", 10s))
      << macsim.output();
  EXPECT_TRUE(macsim.running());
  macsim.signal(SIGTERM);
  EXPECT_EQ(macsim.wait_for_exit(10s), 0) << macsim.output();
}

TEST(MacsimCli, AWorldNamedAloneIsFoundAmongTheSharedWorlds) {
  // No small_room.xml where the test runs: the one in share/macsim/worlds beside bin/ is loaded.
  ASSERT_FALSE(std::filesystem::exists("small_room.xml"));
  ChildProcess p({bin("macsim"), "--world", "small_room.xml", "--validate"});
  ASSERT_EQ(p.wait_for_exit(20s), 0) << p.output();
  EXPECT_NE(p.output().find("4 objects (3 portable"), std::string::npos) << p.output();
  // A name that is nowhere is still an error naming it.
  ChildProcess missing({bin("macsim"), "--world", "no_such_world.xml", "--validate"});
  EXPECT_NE(missing.wait_for_exit(20s), 0) << missing.output();
  EXPECT_NE(missing.output().find("no_such_world.xml"), std::string::npos) << missing.output();
}

TEST(MacsimCli, RunsForADurationAsFastAsPossibleAndReportsTheStepRate) {
  ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                  std::to_string(unique_test_domain()), "--as-fast-as-possible", "--duration",
                  "2"});
  ASSERT_EQ(p.wait_for_exit(60s), 0) << p.output();
  EXPECT_NE(p.output().find("rt/kurt/cmd_vel"), std::string::npos) << p.output();
  EXPECT_NE(p.output().find("stopped at sim time 2.000 s after 2000 steps"), std::string::npos)
      << p.output();
}

// The log's levels: --quiet keeps warnings and errors only (the banner, the step rate and the
// summary are information), --log-timestamps puts the time and level before each line.
TEST(MacsimCli, QuietLeavesOnlyWarningsAndTimestampsMarkEachLine) {
  const std::string domain = std::to_string(unique_test_domain());
  ChildProcess quiet({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain", domain,
                      "--as-fast-as-possible", "--duration", "0.2", "--cameras", "off", "--quiet"});
  ASSERT_EQ(quiet.wait_for_exit(60s), 0) << quiet.output();
  EXPECT_EQ(quiet.output().find("stepping"), std::string::npos) << quiet.output();
  EXPECT_EQ(quiet.output().find("stopped at sim time"), std::string::npos) << quiet.output();
  ChildProcess stamped({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                        domain, "--as-fast-as-possible", "--duration", "0.2", "--cameras", "off",
                        "--log-timestamps"});
  ASSERT_EQ(stamped.wait_for_exit(60s), 0) << stamped.output();
  EXPECT_TRUE(std::regex_search(
      stamped.output(),
      std::regex(R"(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\.\d{3} info  macsim: stepping)")))
      << stamped.output();
  // A usage error is an error: --quiet does not hide it.
  ChildProcess bad({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain", domain,
                    "--seed", "-5", "--quiet"});
  EXPECT_EQ(bad.wait_for_exit(30s), 2);
  EXPECT_NE(bad.output().find("--seed must be 0 or more"), std::string::npos) << bad.output();
}

// One voice: with --log-timestamps every line macsim writes starts with the time and the level,
// sim_core's too. Each of sim_core's voices is provoked: the loader (an unknown element), the
// cameras (no EGL vendor library: no offscreen renderer) and the session writer (/dev/full).
// A session that could not be written completely is said so, and the exit is 1.
TEST(MacsimCli, WithTimestampsEveryLineCarriesTheTimeAndTheLevelSimCoresToo) {
  const std::string world = ::testing::TempDir() + "teleporter_world.xml";
  std::ofstream(world) << "<WORLD>\n<ROBOT><ID>kurt</ID><TYPE>kurt3d</TYPE></ROBOT>\n"
                          "<TELEPORTER/>\n</WORLD>\n";
  const ScopedEnv no_egl("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/egl_vendor.json");
  ChildProcess p({bin("macsim"), "--world", world, "--domain", std::to_string(unique_test_domain()),
                  "--as-fast-as-possible", "--duration", "0.2", "--log-timestamps",
                  "--record-session", "/dev/full"});
  ASSERT_EQ(p.wait_for_exit(60s), 1) << p.output();
  const std::string stamp = R"(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\.\d{3} )";
  for (const auto& [level, what] : std::vector<std::pair<std::string, std::string>>{
           {"warning", world + ":3: warning: unknown element <TELEPORTER>"},
           {"error", "camera rig for 'kurt': "},
           {"error", "macsim: cannot write the session /dev/full"},
           {"error", "macsim: the session /dev/full is incomplete"}}) {
    EXPECT_NE(p.output().find(" " + level + " " + what), std::string::npos)
        << level << " " << what << "\n"
        << p.output();
  }
  EXPECT_EQ(p.output().find("session recorded to"), std::string::npos) << p.output();
  std::istringstream lines(p.output());
  int stamped = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line.rfind("  ", 0) == 0) continue;  // a listing's continued lines
    EXPECT_TRUE(std::regex_search(line, std::regex("^" + stamp + "(debug|info |warning|error) ")))
        << line;
    ++stamped;
  }
  EXPECT_GE(stamped, 6) << p.output();
}

// Running unpaced, the simulation waits for a busy renderer: every stereo pair due in sim time
// is rendered (60 Hz of 640x480 outruns the renderers at thousands of steps per second).
TEST(MacsimCli, AsFastAsPossibleRendersEveryCameraFrameDue) {
  ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                  std::to_string(unique_test_domain()), "--as-fast-as-possible", "--duration", "2",
                  "--cameras", "640x480", "--camera-rate", "60"});
  ASSERT_EQ(p.wait_for_exit(60s), 0) << p.output();
  // The instants the run reaches: 0.001 + k/60 s from its first step, k = 0 .. 119 (k = 120
  // would be at 2.001 s, after the last step): 120 pairs, none skipped, every one counted once
  // rendered, however the renderers were timed.
  EXPECT_NE(p.output().find("cameras: 120 stereo pairs rendered, 0 skipped"), std::string::npos)
      << p.output();
}

TEST(MacsimCli, SigtermAndSigintStopCleanly) {
  for (int sig : {SIGTERM, SIGINT}) {
    ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                    std::to_string(unique_test_domain())});
    ASSERT_TRUE(p.wait_for_output("stepping", 20s)) << p.output();
    p.signal(sig);
    EXPECT_EQ(p.wait_for_exit(10s), 0) << p.output();
    EXPECT_NE(p.output().find("macsim: stopped at sim time"), std::string::npos) << p.output();
  }
}

TEST(MacsimCli, SignalsEndTheProcessWithinASecondWhateverItRuns) {
  // The slowest pacing allowed (a step every second of wall time), a huge step request from a
  // controller being served as fast as possible, and a paused run.
  for (const char* mode : {"--rtf 0.001", "--as-fast-as-possible", "--lockstep"}) {
    SCOPED_TRACE(mode);
    std::vector<std::string> argv{bin("macsim"),
                                  "--world",
                                  source("worlds/small_room.xml"),
                                  "--domain",
                                  std::to_string(unique_test_domain()),
                                  "--cameras",
                                  "off"};
    std::istringstream words(mode);
    for (std::string w; words >> w;) argv.push_back(w);
    ChildProcess p(argv);
    ASSERT_TRUE(p.wait_for_output("stepping", 20s)) << p.output();
    std::this_thread::sleep_for(300ms);
    const auto start = std::chrono::steady_clock::now();
    p.signal(SIGTERM);
    EXPECT_EQ(p.wait_for_exit(5s), 0) << p.output();
    const auto took = std::chrono::steady_clock::now() - start;
    EXPECT_LT(took, 1s) << std::chrono::duration<double>(took).count() << " s";
  }
}

// Local IPv4 addresses (as /proc/net/udp's hex) of the UDP sockets a process holds.
std::vector<std::string> udp_local_addresses(pid_t pid) {
  std::set<std::string> inodes;
  const std::string fd_dir = "/proc/" + std::to_string(pid) + "/fd";
  if (DIR* dir = opendir(fd_dir.c_str())) {
    while (dirent* entry = readdir(dir)) {
      char target[256] = {};
      const std::string link = fd_dir + "/" + entry->d_name;
      if (readlink(link.c_str(), target, sizeof(target) - 1) > 0 &&
          std::string(target).rfind("socket:[", 0) == 0) {
        inodes.insert(std::string(target).substr(8, std::string(target).size() - 9));
      }
    }
    closedir(dir);
  }
  std::vector<std::string> addresses;
  std::ifstream udp("/proc/net/udp");
  std::string line;
  std::getline(udp, line);  // header
  while (std::getline(udp, line)) {
    std::istringstream fields(line);
    std::string slot, local, remote, state, queues, timer, retransmit, uid, timeout, inode;
    fields >> slot >> local >> remote >> state >> queues >> timer >> retransmit >> uid >> timeout >>
        inode;
    if (inodes.count(inode)) addresses.push_back(local.substr(0, 8));
  }
  return addresses;
}

TEST(DdsProfile, TheShippedProfileKeepsEverySocketOnLoopback) {
  // ctest runs this with FASTRTPS_DEFAULT_PROFILES_FILE=deploy/dds/localhost.xml.
  ChildProcess p({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                  std::to_string(unique_test_domain())});
  ASSERT_TRUE(p.wait_for_output("stepping", 20s)) << p.output();
  const auto addresses = udp_local_addresses(p.pid());
  ASSERT_FALSE(addresses.empty()) << "macsim holds no UDP socket";
  for (const auto& a : addresses) {
    // 127.0.0.1 is 0100007F; the SPDP multicast group 239.255.0.1 (joined on lo) is 0100FFEF.
    EXPECT_TRUE(a == "0100007F" || a == "0100FFEF") << "a UDP socket bound to " << a;
  }
}

TEST(MacsimCli, SnapshotsRenderEveryCameraModeOffscreen) {
  std::vector<std::string> argv{bin("macsim"), "--world", source("worlds/DemoWorld_v1.xml"),
                                "--settle",    "0.2",     "--snapshot-size",
                                "320x240"};
  const std::vector<std::string> modes{"MouseOnly", "MouseKeyboard", "FixedFollow", "Follow",
                                       "Inside",    "LeftCamera",    "RightCamera", "Manual"};
  for (const auto& mode : modes) {
    argv.push_back("--snapshot");
    argv.push_back(mode + ":" + ::testing::TempDir() + "snapshot_" + mode + ".png");
  }
  ChildProcess p(argv);
  ASSERT_EQ(p.wait_for_exit(60s), 0) << p.output();
  for (const auto& mode : modes) {
    const cv::Mat image = macsim::images::read_image(::testing::TempDir() + "snapshot_" + mode + ".png");
    ASSERT_FALSE(image.empty()) << mode;
    EXPECT_EQ(image.size(), cv::Size(320, 240)) << mode;
    cv::Scalar mean, stddev;
    cv::meanStdDev(image, mean, stddev);
    EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 20) << mode << " is featureless";
  }
  ChildProcess bad(
      {bin("macsim"), "--world", source("worlds/DemoWorld_v1.xml"), "--snapshot", "Fisheye:x.png"});
  EXPECT_EQ(bad.wait_for_exit(20s), 2);
  EXPECT_NE(bad.output().find("MODE one of MouseOnly"), std::string::npos) << bad.output();
}

TEST(MacsimCli, TheViewerOpensARealWindowOnAnXServer) {
  // A private X server (Xvfb) on a display number derived from a reserved DDS domain.
  const int domain = unique_test_domain();
  const std::string display = ":" + std::to_string(domain);
  ChildProcess xvfb({"/usr/bin/Xvfb", display, "-screen", "0", "1024x768x24", "-nolisten", "tcp"});
  ASSERT_TRUE(std::filesystem::exists("/usr/bin/Xvfb"));
  std::this_thread::sleep_for(1s);
  ASSERT_TRUE(xvfb.running()) << xvfb.output();
  const std::string shot = ::testing::TempDir() + "viewer_window.png";
  std::filesystem::remove(shot);
  setenv("DISPLAY", display.c_str(), 1);
  ChildProcess viewer({bin("macsim"), "--world", source("worlds/DemoWorld_v1.xml"), "--domain",
                       std::to_string(domain), "--viewer", "--camera-mode", "FixedFollow",
                       "--viewer-screenshot", shot, "--duration", "2.0"});
  unsetenv("DISPLAY");
  ASSERT_EQ(viewer.wait_for_exit(60s), 0) << viewer.output();
  const cv::Mat image = macsim::images::read_image(shot);
  ASSERT_FALSE(image.empty()) << viewer.output();
  EXPECT_EQ(image.size(), cv::Size(960, 720));
  cv::Scalar mean, stddev;
  cv::meanStdDev(image, mean, stddev);
  EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 20);
}

TEST(MacsimCli, TheViewerWithoutADisplaySaysSo) {
  unsetenv("DISPLAY");
  ChildProcess viewer({bin("macsim"), "--world", source("worlds/small_room.xml"), "--domain",
                       std::to_string(unique_test_domain()), "--viewer"});
  EXPECT_EQ(viewer.wait_for_exit(30s), 1);
  EXPECT_NE(viewer.output().find("no X display"), std::string::npos) << viewer.output();
}

TEST(HelloKurtCli, WithoutASimulatorItSaysSoAndExitsTwo) {
  ChildProcess p({bin("helloKurt"), "--domain", std::to_string(unique_test_domain()),
                  "--discovery-timeout", "2"});
  EXPECT_EQ(p.wait_for_exit(20s), 2) << p.output();
  EXPECT_NE(p.output().find("no odometry from robot 'kurt'"), std::string::npos) << p.output();
}

}  // namespace
}  // namespace macsim::test
