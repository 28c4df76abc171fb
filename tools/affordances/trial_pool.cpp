#include "trial_pool.h"

#include <condition_variable>
#include <deque>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <thread>

#include "macsim/dds/log.h"
#include "macsim/process/child_process.h"

namespace affordances {

namespace {

/// Times a lost simulator of this run that still runs is connected to again.
constexpr int kReconnects = 3;
/// Times a simulator of this run whose process died is started again.
constexpr int kRestarts = 3;

/// The last `lines` lines of a text file (or what there is).
std::string log_tail(const std::string& file, std::size_t lines) {
  std::ifstream in(file);
  std::deque<std::string> last;
  for (std::string line; std::getline(in, line);) {
    last.push_back(line);
    if (last.size() > lines) last.pop_front();
  }
  std::string text;
  for (const auto& line : last) text += "  | " + line + "\n";
  return text;
}

/// The trials left, shared by the workers.
class TrialQueue {
 public:
  explicit TrialQueue(const std::vector<TrialSpec>& trials) : left_(trials.begin(), trials.end()) {}
  /// The next trial; false once none is left and none is under way (one under way may yet
  /// come back from a lost instance).
  bool take(TrialSpec& out) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return !left_.empty() || running_ == 0; });
    if (left_.empty()) return false;
    out = left_.front();
    left_.pop_front();
    ++running_;
    return true;
  }
  void finished() {
    std::lock_guard<std::mutex> lock(mutex_);
    --running_;
    changed_.notify_all();
  }
  /// A trial whose instance was lost goes back first.
  void give_back(const TrialSpec& trial) {
    std::lock_guard<std::mutex> lock(mutex_);
    left_.push_front(trial);
    --running_;
    changed_.notify_all();
  }
  std::vector<TrialSpec> rest() {
    std::lock_guard<std::mutex> lock(mutex_);
    return {left_.begin(), left_.end()};
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<TrialSpec> left_;
  int running_ = 0;
};

}  // namespace

PoolSummary TrialPool::run(const std::vector<TrialSpec>& trials,
                           const std::function<void(const TrialRecord&)>& done) {
  TrialQueue queue(trials);
  PoolSummary summary;
  std::mutex report;  // one `done` call and one message at a time
  std::vector<int> domains = options_.attach;
  if (domains.empty()) {
    for (int i = 0; i < options_.instances; ++i) domains.push_back(options_.first_domain + i);
  }

  auto worker = [&](int index, int domain) {
    std::unique_ptr<macsim::process::ChildProcess> simulator;
    auto say = [&](const std::string& text) {
      std::lock_guard<std::mutex> lock(report);
      macsim::log::warn("\naffordance_trials: instance {} (domain {}): {}", index, domain, text);
    };
    // A simulator of this run, started (again: `start` > 0) with its log in a file of its own.
    auto start_simulator = [&](int start) {
      std::vector<std::string> argv{macsim::process::sibling_program("macsim"),
                                    "--world",
                                    options_.world,
                                    "--domain",
                                    std::to_string(domain),
                                    "--lockstep",
                                    "--cameras",
                                    options_.cameras,
                                    "--camera-rate",
                                    std::to_string(options_.instance.camera_rate)};
      if (!options_.instance.profile.empty()) {
        argv.insert(argv.end(), {"--profile", options_.instance.profile});
      }
      macsim::process::Options output;
      output.output = macsim::process::Output::file(
          options_.log_dir + "/macsim_domain_" + std::to_string(domain) +
          (start > 0 ? ".restart" + std::to_string(start) : "") + ".log");
      simulator.reset();  // a dead one reaped before its domain is taken again
      simulator = std::make_unique<macsim::process::ChildProcess>(argv, output);
    };
    // How a simulator of ours ended, with its last words.
    auto how_it_ended = [&] {
      return "the simulator ended with exit code " +
             std::to_string(simulator->wait_for_exit(std::chrono::milliseconds(0)).value_or(-1)) +
             "; the end of " + simulator->output_path() + ":\n" +
             log_tail(simulator->output_path(), 20);
    };
    try {
      if (options_.attach.empty()) start_simulator(0);
      InstanceOptions o = options_.instance;
      o.domain = domain;
      // Connects and plays trials until none is left; throws InstanceLost, its trial given back.
      auto play_trials = [&] {
        TrialRobot robot(o);
        robot.connect(std::chrono::seconds(30));
        TrialSpec trial;
        while (queue.take(trial)) {
          try {
            TrialRecord record = robot.run(trial);
            record.instance = index;
            {
              std::lock_guard<std::mutex> lock(report);
              ++summary.done;
              done(record);
            }
            queue.finished();
          } catch (const InstanceLost&) {
            queue.give_back(trial);
            throw;
          } catch (const std::exception& e) {
            say("trial " + std::to_string(trial.seed) + " refused: " + e.what());
            queue.finished();
            std::lock_guard<std::mutex> lock(report);
            ++summary.failed;
          }
        }
      };
      // A simulator of ours lost while its process still runs (unmatched or silent under a
      // heavy load) is connected to again, one whose process died is started again, a few
      // times each: the trial under way starts over from its reset.
      for (int reconnects = 0, restarts = 0;;) {
        try {
          play_trials();
          break;
        } catch (const InstanceLost& e) {
          if (!simulator) throw;  // attached to: not ours to start again
          if (simulator->running()) {
            if (reconnects == kReconnects) throw;
            say(std::string("lost: ") + e.what() +
                "; its simulator still runs: connecting again (" + std::to_string(++reconnects) +
                " of " + std::to_string(kReconnects) + ")");
            std::lock_guard<std::mutex> lock(report);
            ++summary.reconnects;
            continue;
          }
          if (restarts == kRestarts) throw;
          say(std::string("lost: ") + e.what() + " (" + how_it_ended() +
              "); starting its simulator again (" + std::to_string(++restarts) + " of " +
              std::to_string(kRestarts) + "): the trial under way plays again from its reset");
          start_simulator(restarts);
          std::lock_guard<std::mutex> lock(report);
          ++summary.restarts;
        }
      }
    } catch (const std::exception& e) {
      // How it ended and its last words, so that a lost instance can be understood later.
      const std::string ended =
          simulator && !simulator->running() ? " (" + how_it_ended() + ")" : "";
      say(std::string("lost: ") + e.what() + ended + "; its trials go to the other instances");
      std::lock_guard<std::mutex> lock(report);
      ++summary.lost_instances;
    }
  };

  std::vector<std::thread> workers;
  for (std::size_t i = 0; i < domains.size(); ++i)
    workers.emplace_back(worker, static_cast<int>(i), domains[i]);
  for (auto& w : workers) w.join();
  summary.not_run = queue.rest();
  return summary;
}

}  // namespace affordances
