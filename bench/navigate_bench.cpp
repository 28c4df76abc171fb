// The navigator over many clutter layouts, both policies in the same run: for each seed,
// macsim --lockstep --seed N on worlds/clutter_field.xml and kurt_navigate --lockstep stepping
// it, once with the traverse model and once avoiding everything, judged from the world state
// (at the goal: within 0.5 m of it by ground truth; the things driven through and around,
// tests/support/clutter_judge.h). Prints per policy the
// success rate, the median robot time of the runs that got there, the stalls, and per kind of
// thing how often it was driven through and around. `name value unit` lines, then the tables.
//   bench_navigate [--domain N] [--policy P] [--draw DIR] --affordances DIR [SEEDS [FIRST]]
//   (default 50 seeds from 1; repository root)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <string>
#include <thread>
#include <vector>

#include "domain_arg.h"
#include "macsim/client/robot_devices.h"
#include "macsim/client/supervisor_client.h"
#include "macsim/images/image_files.h"
#include "macsim/process/child_process.h"
#include "support/clutter_judge.h"
#include "support/world_view.h"

namespace {

using namespace std::chrono_literals;
using macsim::test::ClutterJudgement;

struct Tally {
  int runs = 0, successes = 0, stalls = 0;
  std::vector<double> robot_times;                   // of the runs at the goal
  std::map<std::string, std::pair<int, int>> kinds;  // through, around
  std::vector<int> failed;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

/// A number after the last `key` in `line`, or 0 (a failure's reason may hold the key too).
double number_after(const std::string& line, const std::string& key) {
  const auto at = line.rfind(key);
  return at == std::string::npos ? 0.0 : std::atof(line.c_str() + at + key.size());
}

/// Where the navigator said it stood ("[t= T s] at X,Y," lines of its log, odometry frame),
/// with its robot time T.
struct Belief {
  double t;
  Eigen::Vector2d at;
};
std::vector<Belief> believed_path(const std::string& log) {
  std::ifstream in(log);
  std::vector<Belief> said;
  std::string line;
  while (std::getline(in, line)) {
    const auto t = line.find("[t=");
    const auto k = line.find("] at ");
    double time = 0, x = 0, y = 0;
    if (t != std::string::npos && k != std::string::npos &&
        std::sscanf(line.c_str() + t + 3, "%lf", &time) == 1 &&
        std::sscanf(line.c_str() + k + 5, "%lf,%lf", &x, &y) == 2)
      said.push_back({time, {x, y}});
  }
  return said;
}

/// A picture of one run from above (east to the right): the things where they stood (grey) and
/// where they ended (coloured by kind), the robot's path by ground truth (blue), where the
/// navigator believed it stood at each look (red, a line to where it stood then) and the goal
/// (green).
void draw_run(const std::string& file,
              const std::map<std::string, macsim_msgs::msg::dds_::Object_>& before,
              const std::map<std::string, macsim_msgs::msg::dds_::Object_>& after,
              const std::vector<Eigen::Vector2d>& path, const std::vector<double>& stamps,
              const std::vector<Belief>& said) {
  constexpr double kScale = 100, kX0 = -1.2, kY0 = 1.7;  // px per m; the picture's top left
  cv::Mat image(static_cast<int>(2 * kY0 * kScale), static_cast<int>(8.9 * kScale), CV_8UC3,
                cv::Scalar(255, 255, 255));
  const auto px = [&](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>((p.x() - kX0) * kScale),
                     static_cast<int>((kY0 - p.y()) * kScale));
  };
  const std::map<std::string, cv::Scalar> colours{
      // BGR
      {"box", {40, 40, 200}},       {"post", {90, 90, 90}},       {"step", {60, 90, 140}},
      {"passage", {130, 130, 130}}, {"doorstep", {60, 120, 180}}, {"joist", {40, 170, 170}},
      {"log", {30, 80, 130}},       {"sphere", {200, 80, 200}}};
  for (const auto& [name, o] : before)
    for (const auto& p : macsim::test::footprint(o))
      cv::circle(image, px(p), 1, {200, 200, 200}, -1);
  for (const auto& [name, o] : after) {
    const auto c = colours.find(ClutterJudgement::kind(name));
    const cv::Scalar colour = c != colours.end() ? c->second : cv::Scalar(0, 0, 0);
    for (const auto& p : macsim::test::footprint(o)) cv::circle(image, px(p), 1, colour, -1);
  }
  cv::circle(image, px({6, 0}), static_cast<int>(0.5 * kScale), {0, 160, 0}, 1);
  for (std::size_t k = 1; k < path.size(); ++k)
    cv::line(image, px(path[k - 1]), px(path[k]), {200, 100, 0}, 1);
  for (const auto& b : said) {
    cv::circle(image, px(b.at), 3, {0, 0, 230}, 1);
    // Where it stood then: the truth stamped nearest its robot time (it starts at the first).
    const auto k = std::lower_bound(stamps.begin(), stamps.end(), stamps.front() + b.t);
    if (k != stamps.end()) cv::line(image, px(b.at), px(path[k - stamps.begin()]), {0, 0, 230}, 1);
  }
  macsim::images::write_image(file, image);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::vector<std::string> policies{"model", "avoid"};
  for (std::size_t k = 0; k + 1 < args.size(); ++k) {
    if (args[k] != "--policy") continue;
    if (args[k + 1] != "model" && args[k + 1] != "avoid") {
      std::fprintf(stderr, "bench_navigate: --policy is model or avoid, not '%s'\n",
                   args[k + 1].c_str());
      return 2;
    }
    policies = {args[k + 1]};
    args.erase(args.begin() + static_cast<std::ptrdiff_t>(k),
               args.begin() + static_cast<std::ptrdiff_t>(k) + 2);
    break;
  }
  const auto domain_base =
      macsim::bench::take_domain_base(args, "bench_navigate", macsim::bench::kLayoutDomainBase);
  if (!domain_base) return 2;
  bool verbose = false;  // the navigator's --verbose, into its logs
  if (const auto v = std::find(args.begin(), args.end(), "--verbose"); v != args.end()) {
    verbose = true;
    args.erase(v);
  }
  std::string draw;  // a folder for a picture of each run
  for (std::size_t k = 0; k + 1 < args.size(); ++k) {
    if (args[k] != "--draw") continue;
    draw = args[k + 1];
    std::filesystem::create_directories(draw);
    args.erase(args.begin() + static_cast<std::ptrdiff_t>(k),
               args.begin() + static_cast<std::ptrdiff_t>(k) + 2);
    break;
  }
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::printf(
        "usage: bench_navigate [--domain N] [--policy model|avoid] [--draw DIR] [--verbose] "
        "--affordances DIR [SEEDS [FIRST]]\n  "
        "kurt_navigate against "
        "macsim in lock-step on SEEDS layouts of worlds/clutter_field.xml (default 50 from "
        "seed 1), with the traverse model DIR/traverse.yml and with --policy avoid (or only the "
        "one --policy names); prints each "
        "policy's success rate, median robot time, stalls, and what it drove through and around "
        "by kind; --draw writes a picture of each run into DIR (POLICY_SEED.png: the things before "
        "and after, the path by ground truth, where the navigator believed it stood); --verbose "
        "keeps each look's fit and things in the navigator's logs. Run from the repository root. "
        "Each run has a DDS domain of its own among the 80 from --domain "
        "(default 10).\n");
    return 0;
  }
  int seeds = 50, first = 1;
  if (args.size() < 2 || args[0] != "--affordances" || args.size() > 4 ||
      (args.size() > 2 && (seeds = std::atoi(args[2].c_str())) <= 0) ||
      (args.size() > 3 && (first = std::atoi(args[3].c_str())) < 0)) {
    std::fprintf(stderr,
                 "bench_navigate: --affordances DIR is required; SEEDS must be positive and FIRST "
                 "not negative (--help)\n");
    return 2;
  }
  const std::string models = args[1];
  const std::string world = "worlds/clutter_field.xml";
  if (!std::filesystem::exists(world)) {
    std::fprintf(stderr, "bench_navigate: run it from the repository root (%s not found)\n",
                 world.c_str());
    return 2;
  }
  const std::string bin = std::filesystem::canonical("/proc/self/exe").parent_path().string();
  const std::string logs =
      std::filesystem::temp_directory_path() / ("bench_navigate_" + std::to_string(getpid()));
  std::filesystem::create_directories(logs);
  std::map<std::string, Tally> tallies;
  for (int seed = first; seed < first + seeds; ++seed) {
    for (const std::string& policy : policies) {
      const int domain =
          *domain_base + (2 * seed + (policy == "avoid")) % macsim::bench::kLayoutDomains;
      const std::string tag = policy + "_" + std::to_string(seed);
      macsim::process::ChildProcess sim(
          {bin + "/macsim", "--world", world, "--domain", std::to_string(domain), "--lockstep",
           "--seed", std::to_string(seed)},
          macsim::process::Output::file(logs + "/macsim_" + tag + ".log"));
      macsim::dds::Participant participant({domain, "", "bench_navigate"});
      macsim::test::WorldView view(participant);
      std::map<std::string, macsim_msgs::msg::dds_::Object_> before;
      // The field's things before the robot moves (a lock-step simulator publishes the
      // world's state after a step).
      macsim::client::SimulationClient simulation(participant);
      if (!simulation.step(1, std::chrono::seconds(30))) {
        std::fprintf(stderr, "bench_navigate: seed %d: the simulator did not step\n", seed);
        return 1;
      }
      for (int i = 0; i < 3000; ++i) {
        before = view.snapshot();
        int clutter = 0;
        for (const auto& [name, o] : before) clutter += o.user_data() == "clutter";
        if (clutter == macsim::test::kClutterFieldThings) break;
        std::this_thread::sleep_for(10ms);
      }
      std::vector<std::string> command{bin + "/kurt_navigate", "--domain", std::to_string(domain),
                                       "--lockstep",           "--policy", policy};
      if (verbose) command.push_back("--verbose");
      if (policy == "model") command.insert(command.end(), {"--affordances", models});
      const std::string log = logs + "/kurt_navigate_" + tag + ".log";
      macsim::process::ChildProcess navigator(command, macsim::process::Output::file(log));
      const auto ended = navigator.wait_for_exit(std::chrono::seconds(600));
      const int code = ended ? *ended : navigator.stop();
      std::this_thread::sleep_for(300ms);
      const auto after = view.snapshot();
      std::vector<Eigen::Vector2d> path;
      std::vector<double> stamps;
      for (const auto& t : view.truth.all()) {
        path.emplace_back(t.pose().pose().position().x(), t.pose().pose().position().y());
        stamps.push_back(macsim::client::stamp_seconds(t.header()));
      }
      sim.stop(std::chrono::seconds(10));
      std::ifstream in(log);
      std::string line, last;
      while (std::getline(in, line)) last = line;
      const ClutterJudgement judged(before, after, path);
      if (!draw.empty())
        draw_run(draw + "/" + tag + ".png", before, after, path, stamps, believed_path(log));
      Tally& t = tallies[policy];
      ++t.runs;
      t.stalls += static_cast<int>(number_after(last, "stalls "));
      // At the goal by the world's ground truth, not only by the robot's word.
      const bool there =
          code == 0 && !path.empty() && (path.back() - Eigen::Vector2d(6, 0)).norm() < 0.5;
      if (there) {
        ++t.successes;
        t.robot_times.push_back(number_after(last, "robot time "));
      } else {
        t.failed.push_back(seed);
      }
      for (const auto& n : judged.through) ++t.kinds[ClutterJudgement::kind(n)].first;
      for (const auto& n : judged.around) ++t.kinds[ClutterJudgement::kind(n)].second;
      std::fprintf(stderr,
                   "seed %d %s: exit %d%s, robot time %.1f s, stalls %.0f, through %zu, around "
                   "%zu\n",
                   seed, policy.c_str(), code,
                   code == 0 && !there ? " (not at the goal by ground truth)" : "",
                   number_after(last, "robot time "), number_after(last, "stalls "),
                   judged.through.size(), judged.around.size());
    }
  }
  for (const auto& [policy, t] : tallies) {
    std::printf("navigate_%s_runs %d count\n", policy.c_str(), t.runs);
    std::printf("navigate_%s_success_rate %.3f ratio\n", policy.c_str(),
                static_cast<double>(t.successes) / t.runs);
    std::printf("navigate_%s_robot_time_median %.1f s\n", policy.c_str(), median(t.robot_times));
    std::printf("navigate_%s_stalls %d count\n", policy.c_str(), t.stalls);
  }
  for (const auto& [policy, t] : tallies) {
    std::printf("\n%s: driven through / around, by kind (over %d runs)\n", policy.c_str(), t.runs);
    for (const auto& [kind, counts] : t.kinds)
      std::printf("  %-16s %4d %4d\n", kind.c_str(), counts.first, counts.second);
    std::string list;
    for (int s : t.failed) list += " " + std::to_string(s);
    if (!list.empty()) std::printf("  not at the goal: seeds%s\n", list.c_str());
  }
  bool any_failed = false;
  for (const auto& [policy, t] : tallies) any_failed |= !t.failed.empty();
  if (any_failed)
    std::fprintf(stderr, "bench_navigate: logs in %s\n", logs.c_str());
  else
    std::filesystem::remove_all(logs);
  return 0;
}
