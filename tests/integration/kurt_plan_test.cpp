// kurt_plan end to end against macsim in lock-step, judged from the simulator's world state: on
// a switch stiffer than one can it reaches the door by a plan over the hand-written domain,
// watching each step and planning again when a can does not come up and when the first can
// leaves the switch up, where the script drops one can and waits at a closed door; the plan as
// it acts is on rt/kurt/plan; the problem files it writes are the scene as PDDL, and plan as it
// did; a goal no can of the room serves (a blue can on the switch when the blue cans are lead)
// is unreachable, said with its own exit code; where no can can be lifted it pushes a box onto a
// switch plate flush with the floor; it crosses a way cluttered with joists, logs and posts,
// judging what stands in its way by a learned traverse model;
// its overview pictures carry the plan; bad arguments move nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>

#include "macsim/affordances/planner.h"
#include "macsim/images/image_files.h"
#include "macsim/sim_core/world_loader.h"
#include "macsim/sim_core/world_variation.h"
#include "support/demonstrator_run.h"

namespace macsim::test {
namespace {

using namespace std::chrono_literals;
namespace pddl = macsim::affordances::pddl;

const std::string kByHand = "affordances/domains/kurt3d_room_by_hand.pddl";

TEST(KurtPlan, AGoalNoPlanReachesExitsFourSayingWhy) {
  // The demonstrator's room as written: its two blue cans are lead. One is tried and does not
  // come up; the other has its colour, and nothing else can be put on the switch in blue.
  const DemoRun run = play_demonstrator("kurt_plan", source("worlds/DemoWorld_v1.xml"), -1,
                                        {"--pddl-domain", source(kByHand), "--goal", "on-switch:blue"});
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(run.output.find("(lift blue_"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("not as predicted"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("the goal cannot be reached"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("goal reached: no"), std::string::npos) << run.output;
  ASSERT_TRUE(run.door.has_value());
  EXPECT_FALSE(run.door->door().triggered());
  EXPECT_EQ(can_on_platform(run), nullptr);
}

/// The robot time a controller's summary line gives ("robot time 12.3 s" or "robot time: 12.3 s").
double robot_time(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex("robot time:? ([0-9.]+) s"))) return -1;
  return std::stod(m[1]);
}

TEST(KurtPlan, AnOpenDoorIsDrivenThroughAtOnceWhereTheScriptFetchesACanFirst) {
  const std::string world = source("worlds/goals/door_open.xml");
  TempDir pictures("kurt_plan_pictures_");
  const DemoRun plan = play_demonstrator("kurt_plan", world, 5, {"--pddl-domain", source(kByHand), "--pictures"},
                                         std::chrono::seconds(170), {"--pictures", pictures.path()});
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("plan of 2 step(s)"), std::string::npos) << plan.output;
  // Seen from the start across the room, the door is approached before its wall is watched.
  EXPECT_NE(plan.output.find("going toward the door seen at"), std::string::npos) << plan.output;
  EXPECT_NE(plan.output.find("(go start door): as predicted"), std::string::npos) << plan.output;
  // After each step an overview picture, and beside it the same with the plan drawn on its right.
  for (const char* step : {"plan_1_step_1", "plan_1_step_2"}) {
    const cv::Mat taken = macsim::images::read_image(pictures.path() + "/" + step + ".png");
    const cv::Mat drawn = macsim::images::read_image(pictures.path() + "/" + step + "_plan.png");
    ASSERT_FALSE(taken.empty()) << step << "\n" << plan.output;
    ASSERT_FALSE(drawn.empty()) << step << "\n" << plan.output;
    ASSERT_EQ(drawn.rows, taken.rows);
    ASSERT_GT(drawn.cols, taken.cols);
    EXPECT_EQ(cv::norm(drawn(cv::Rect(0, 0, taken.cols, taken.rows)), taken, cv::NORM_INF), 0.0);
    // The panel holds text: bright pixels on its dark ground.
    cv::Mat panel;
    cv::cvtColor(drawn(cv::Rect(taken.cols, 0, drawn.cols - taken.cols, drawn.rows)), panel, cv::COLOR_BGR2GRAY);
    EXPECT_GT(cv::countNonZero(panel > 150), 200) << step;
  }
  EXPECT_EQ(plan.output.find("(lift "), std::string::npos) << plan.output;
  ASSERT_TRUE(plan.truth.has_value());
  EXPECT_GT(plan.truth->pose().pose().position().x(), 1.5 + 0.3);
  EXPECT_EQ(can_on_platform(plan), nullptr);
  // The script gets through too, after lifting a can and dropping it on the switch.
  const DemoRun script = play_demonstrator("kurt_demo", world, 5);
  ASSERT_EQ(script.exit_code, 0) << script.output;
  EXPECT_NE(can_on_platform(script), nullptr);
  const double planned = robot_time(plan.output), scripted = robot_time(script.output);
  ASSERT_GT(planned, 0) << plan.output;
  EXPECT_LT(planned, scripted) << plan.output << "\n" << script.output;
}

TEST(KurtPlan, AStiffSwitchGetsASecondCanWhereTheScriptDropsOneAndWaits) {
  TempDir problems("kurt_plan_problems_");
  const std::string world = source("worlds/goals/stiff_switch.xml");
  // Layout 2: the nearest can does not come up (the plan is made again after it); the first
  // can on the switch leaves it up (not as predicted, planned again, a second can beside it).
  const DemoRun run = play_demonstrator("kurt_plan", world, 2,
                                        {"--pddl-domain", source(kByHand), "--problems", problems.path()});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("goal reached: yes"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("plan of 6 step(s)"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(": not as predicted: perceived no (holding"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(": not as predicted: perceived no (pressed switch)"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("switch door): as predicted"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("(drive-through door): as predicted"), std::string::npos) << run.output;
  std::smatch replans;
  ASSERT_TRUE(std::regex_search(run.output, replans, std::regex("replans: ([0-9]+)"))) << run.output;
  EXPECT_GE(std::stoi(replans[1]), 2);
  // The world says the same: two cans on the platform, the door opened by weight, the robot beyond.
  EXPECT_EQ(cans_on_platform(run).size(), 2u) << run.output;
  ASSERT_TRUE(run.door.has_value());
  EXPECT_TRUE(run.door->door().triggered());
  EXPECT_FALSE(run.door->door().virtually_triggered());
  ASSERT_TRUE(run.truth.has_value());
  EXPECT_GT(run.truth->pose().pose().position().x(), 1.5 + 0.3);
  // The plan as it acted, on rt/kurt/plan: each step under way, then as or not as predicted; the
  // things judged; the summary line at the end.
  namespace plan_msg = plan_msgs::msg::dds_;
  ASSERT_GE(run.plans.size(), 4u) << run.output;
  bool under_way = false, not_as_predicted = false, judged = false;
  for (const auto& shown : run.plans) {
    EXPECT_EQ(shown.goal(), "through-door");
    EXPECT_EQ(shown.header().frame_id(), "odom");
    for (std::size_t i = 0; i < shown.steps().size(); ++i) {
      const auto& step = shown.steps()[i];
      EXPECT_NE(run.output.find(step.action()), std::string::npos) << step.action();
      EXPECT_GT(step.probability(), 0.0);
      EXPECT_LE(step.probability(), 1.0);
      if (step.status() == plan_msg::STEP_UNDER_WAY) {
        under_way = true;
        EXPECT_EQ(shown.current(), static_cast<int>(i));
      }
      if (step.status() == plan_msg::STEP_NOT_AS_PREDICTED) {
        not_as_predicted = true;
        EXPECT_EQ(step.perceived().rfind("not as predicted: perceived no (", 0), 0u) << step.perceived();
      }
    }
    for (const auto& thing : shown.things()) {
      judged = true;
      EXPECT_FALSE(thing.label().empty()) << thing.name();
      EXPECT_GE(thing.confidence(), 0.5) << thing.name();
      EXPECT_LE(thing.confidence(), 1.0) << thing.name();
    }
  }
  EXPECT_TRUE(under_way);
  EXPECT_TRUE(not_as_predicted);
  EXPECT_TRUE(judged);
  EXPECT_GE(run.plans.back().round(), 2u);
  EXPECT_EQ(run.plans.back().outcome().rfind("goal reached: yes, plan steps: ", 0), 0u) << run.plans.back().outcome();
  EXPECT_EQ(run.plans.back().steps().back().status(), plan_msg::STEP_AS_PREDICTED);
  // Each planning round's scene is a problem file of the domain, and the first plans as the
  // run's first plan began.
  const pddl::Domain domain = pddl::load_domain(source(kByHand));
  int files = 0;
  for (const auto& f : std::filesystem::directory_iterator(problems.path())) {
    ++files;
    EXPECT_NO_THROW(pddl::load_problem(f.path().string(), domain)) << f.path();
  }
  EXPECT_GE(files, 2);
  const pddl::Problem first = pddl::load_problem(problems.path() + "/scene-1.pddl", domain);
  const auto plan = macsim::affordances::plan(domain, first);
  ASSERT_TRUE(plan.plan) << plan.reason;
  EXPECT_NE(run.output.find("1. " + plan.plan->steps[0].text() + " -> "), std::string::npos)
      << plan.plan->steps[0].text() << "\n" << run.output;
  // The script drops one and waits at a closed door.
  const DemoRun script = play_demonstrator("kurt_demo", world, 2);
  EXPECT_EQ(script.exit_code, 6) << script.output;
  EXPECT_NE(script.output.find("the door stayed closed"), std::string::npos) << script.output;
  EXPECT_EQ(cans_on_platform(script).size(), 1u) << script.output;
}

TEST(KurtPlan, WhereNoCanCanBeLiftedItPushesABoxOntoTheFlushSwitch) {
  // The push-to-switch family, layout 2: two lead cans, a plastic one, two boxes and a plate flush
  // with the floor (the script exits 5 there: KurtDemo.WhereNoCanCanBeLifted...).
  const DemoRun run = play_demonstrator("kurt_plan", source("worlds/goals/push_to_switch.xml"), 2,
                                        {"--pddl-domain", source(kByHand)});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("plan of 4 step(s)"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("switch door): as predicted"), std::string::npos) << run.output;  // the push
  EXPECT_EQ(run.output.find("(lift "), std::string::npos) << run.output;
  // The world: a box on the plate, the door opened by its weight, the robot beyond.
  const auto plate = run.objects.find("doors/door_00/switch_component/platform");
  ASSERT_NE(plate, run.objects.end());
  int boxes_on = 0;
  for (const auto& [name, object] : run.objects) {
    const auto& p = object.pose().position();
    const auto& at = plate->second.pose().position();
    if (object.user_data() == "box" && std::hypot(p.x() - at.x(), p.y() - at.y()) < 0.25) ++boxes_on;
  }
  EXPECT_EQ(boxes_on, 1) << run.output;
  ASSERT_TRUE(run.door.has_value());
  EXPECT_TRUE(run.door->door().triggered());
  EXPECT_FALSE(run.door->door().virtually_triggered());
  ASSERT_TRUE(run.truth.has_value());
  EXPECT_GT(run.truth->pose().pose().position().x(), 1.5 + 0.3);
}

TEST(KurtPlan, CrossesAClutteredWayToTheSwitchAndTheDoor) {
  // The cluttered-way family, layout 1: joists, logs, balls and posts across the room between
  // the cans and the switch; the robot starts west of them and ends east of the partition.
  // What stands in its way it judges by a traverse model learned from the committed trials, on
  // what the 3D laser gives.
  const std::string world = source("worlds/goals/cluttered_way.xml");
  TempDir learned("kurt_plan_traverse_");
  ChildProcess learn({bin("affordance_learn"), "--in", source("tests/tools/affordances/traverse_trials.csv"),
                      "--features", "shape", "--save-model", learned.path(), "--out",
                      learned.path() + "/plots", "--quiet"});
  ASSERT_EQ(learn.wait_for_exit(60s), 0) << learn.output();
  const DemoRun run = play_demonstrator("kurt_plan", world, 1,
                                        {"--pddl-domain", source(kByHand), "--affordances", learned.path()});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("goal reached: yes"), std::string::npos) << run.output;
  // It stood before something in its way and the model let it drive over it.
  EXPECT_TRUE(std::regex_search(run.output, std::regex("judged what stands at .*P\\(traversable\\) 0\\.[5-9][0-9], over it")))
      << run.output;
  ASSERT_TRUE(run.door.has_value());
  EXPECT_TRUE(run.door->door().triggered());
  ASSERT_TRUE(run.truth.has_value());
  EXPECT_GT(run.truth->pose().pose().position().x(), 1.5 + 0.3);
  // What it drove into rolled away: some of the clutter is not where the layout put it.
  WorldSpec spec = load_world_file(world);
  vary_world(spec, 1);
  int moved = 0;
  for (const auto& o : spec.objects) {
    const auto it = run.objects.find(o.name);
    if (o.user_data != "clutter" || !o.portable || it == run.objects.end()) continue;
    const auto& p = it->second.pose().position();
    moved += std::hypot(p.x() - o.pose.position.x(), p.y() - o.pose.position.y()) > 0.05;
  }
  std::printf("cluttered way, layout 1: %d of the logs and balls moved\n", moved);
}

TEST(KurtPlan, AnswersHelpAndRefusesBadArgumentsWithoutMovingAnything) {
  ChildProcess help({bin("kurt_plan"), "--help"});
  EXPECT_EQ(help.wait_for_exit(10s), 0);
  EXPECT_NE(help.output().find("--goal"), std::string::npos) << help.output();
  TempDir dir("kurt_plan_args_");
  const std::string bad_domain = dir.path() + "/bad.pddl";
  pddl::save_text(bad_domain, "(define (domain d)\n  (:predicates (p))\n  (:action a :effect (q)))\n");
  // A lift model saved as DIR/lift/traverse.yml.
  std::filesystem::create_directories(dir.path() + "/lift");
  ChildProcess learn({bin("affordance_learn"), "--in", source("tests/tools/affordances/lift_trials.csv"),
                      "--save-model", dir.path() + "/lift", "--out", dir.path() + "/plots", "--quiet"});
  ASSERT_EQ(learn.wait_for_exit(60s), 0) << learn.output();
  std::filesystem::rename(dir.path() + "/lift/lift.yml", dir.path() + "/lift/traverse.yml");
  const std::string domain = std::to_string(unique_test_domain());
  const std::string by_hand = source(kByHand);
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  for (const Case& c : std::vector<Case>{
           {{"--pddl-domain", by_hand}, "--domain"},
           {{"--domain", domain}, "give --affordances DIR, --pddl-domain FILE, or both"},
           // Beside the hand-written domain, DIR gives the traverse model: one it cannot take.
           {{"--domain", domain, "--pddl-domain", by_hand, "--affordances", dir.path() + "/lift"},
            dir.path() + "/lift/traverse.yml is a model of lift, not traverse"},
           {{"--domain", domain, "--pddl-domain", by_hand, "--goal", "fly"}, "not 'fly'"},
           {{"--domain", domain, "--pddl-domain", by_hand, "--goal", "on-switch:"}, "on-switch:COLOUR"},
           {{"--domain", domain, "--affordances", dir.path()}, dir.path() + "/effects.ppddl: cannot be read"},
           {{"--domain", domain, "--pddl-domain", bad_domain}, bad_domain + ":3: unknown predicate 'q'"},
           {{"--domain", domain, "--pddl-domain", by_hand, "--problems", dir.path() + "/none"}, "no folder"},
           {{"--domain", domain, "--pddl-domain", by_hand, "--debug-images", dir.path() + "/none"}, "--debug-images " + dir.path() + "/none is no folder"},
           {{"--domain", domain, "--pddl-domain", by_hand, "--timeout", "nan"}, "--timeout"},
           {{"--domain", domain, "--pddl-domain", by_hand, "--policy", "greedy"}, "plan or random, not 'greedy'"},
           {{"--domain", domain, "--pddl-domain", by_hand, "--policy", "random", "--policy-seed", "-3"}, "--policy-seed"}}) {
    std::vector<std::string> argv{bin("kurt_plan")};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    ChildProcess p(argv);
    EXPECT_EQ(p.wait_for_exit(10s), 2) << c.args.back() << "\n" << p.output();
    EXPECT_NE(p.output().find(c.says), std::string::npos) << c.says << "\n" << p.output();
  }
  // No robot: its own exit code after the discovery timeout.
  ChildProcess alone({bin("kurt_plan"), "--domain", domain, "--pddl-domain", by_hand,
                      "--discovery-timeout", "1"});
  EXPECT_EQ(alone.wait_for_exit(30s), 3) << alone.output();
}

}  // namespace
}  // namespace macsim::test
