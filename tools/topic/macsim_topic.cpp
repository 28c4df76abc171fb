// macsim_topic: list, inspect, echo, time, publish, record and replay the topics of a domain,
// with the types of the project's IDL (read from the IDL, never from a hand-kept list).
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <iostream>
#include <map>
#include <mutex>
#include <numeric>
#include <set>
#include <sstream>
#include <thread>

#include "bag.h"
#include "cdr_yaml.h"
#include "macsim/dds/command_line.h"
#include "macsim/dds/dynamic_types.h"
#include "macsim/dds/log.h"
#include "macsim/dds/participant.h"
#include "macsim/msg/rosgraph_msgsPubSubTypes.h"
#include "raw_endpoints.h"
#include "sample_queue.h"
#include "topic_graph.h"

namespace {

namespace dds = macsim::dds;
namespace log = macsim::log;
namespace topic = macsim::topic;
using Clock = std::chrono::steady_clock;
constexpr int kUsage = 2;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }

std::string join(const std::vector<std::string>& items, const char* sep = ", ") {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : sep) + i;
  return out;
}

std::string type_for_people(const std::string& dds_type) { return dds::ros_type_name(dds_type); }

/// The participant of a verb, hearing discovery from its start.
struct Session {
  topic::TopicGraph graph;
  std::unique_ptr<dds::Participant> participant;
  explicit Session(dds::ParticipantOptions options) {
    options.listener = &graph;
    participant = std::make_unique<dds::Participant>(options);
  }
};

/// Sleeps in small slices until `seconds` passed or a signal came; false on a signal.
bool sleep_for(double seconds) {
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < end) {
    if (g_stop.load()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return !g_stop.load();
}

/// The topic's summary once a writer is known; an error naming the topics there are if not.
std::optional<topic::TopicSummary> find_topic(Session& session, const std::string& name,
                                              double wait, int domain) {
  const std::string dds_name = dds::dds_topic_name(name);
  auto found = session.graph.wait_for_writer(
      dds_name, std::chrono::milliseconds(static_cast<int>(wait * 1000)));
  if (found) {
    // let discovery of the other writers of the topic settle
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    return session.graph.topic(dds_name);
  }
  std::vector<std::string> names;
  for (const auto& [n, t] : session.graph.topics()) {
    if (!t.writers.empty()) names.push_back(n);
  }
  log::error("macsim_topic: no writer of '{}' on domain {} after {:g} s; topics with writers: {}",
             dds_name, domain, wait,
             names.empty() ? "none (is a simulator running on this domain?)" : join(names));
  return std::nullopt;
}

topic::WireTypePtr known_type(const std::string& dds_type) {
  auto type = topic::wire_type(dds_type);
  if (!type) {
    std::vector<std::string> names;
    for (const auto& n : dds::idl_type_names()) names.push_back(dds::ros_type_name(n));
    log::error("macsim_topic: '{}' is not a type of the project's IDL; types: {}", dds_type,
               join(names));
  }
  return type;
}

std::string qos_text(const topic::Endpoint& e) {
  return std::string(e.reliable ? "reliable" : "best effort") + ", " +
         (e.transient_local ? "transient local" : "volatile") + (e.keyed ? ", keyed" : "");
}

std::string participants_of(const std::vector<topic::Endpoint>& endpoints) {
  std::vector<std::string> names;
  for (const auto& e : endpoints) {
    if (std::find(names.begin(), names.end(), e.participant) == names.end()) {
      names.push_back(e.participant);
    }
  }
  return join(names);
}

void print_endpoints(const topic::TopicSummary& t) {
  for (const auto* side : {&t.writers, &t.readers}) {
    for (const auto& e : *side) {
      std::cout << "  " << (e.writer ? "writer " : "reader ") << e.guid << " of " << e.participant
                << ": " << type_for_people(e.type) << ", " << qos_text(e) << "\n";
    }
  }
}

// ---- list / info --------------------------------------------------------------------------------

int run_list(int argc, char** argv) {
  dds::ParticipantOptions participant;
  bool verbose = false, types = false;
  double wait = 2.0;
  dds::CommandLine cli("macsim_topic list",
                       "Lists every topic on the domain with its type, writers and readers and "
                       "their participants, from DDS discovery.");
  cli.participant_options(&participant);
  cli.flag("v", "verbose: every writer and reader with its QoS", &verbose);
  cli.flag("t", "show types only beside names (as ros2 topic list -t)", &types);
  cli.option("wait", "SECONDS", "how long to listen to discovery (default 2)", &wait);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (!(wait > 0)) {
    log::error("macsim_topic list: --wait must be positive");
    return kUsage;
  }
  Session session(participant);
  if (!sleep_for(wait)) return 130;
  for (const auto& [name, t] : session.graph.topics()) {
    std::vector<std::string> type_names;
    for (const auto& type : t.types) type_names.push_back(type_for_people(type));
    if (types) {
      std::cout << name << " [" << join(type_names) << "]\n";
      continue;
    }
    std::cout << name << "  " << join(type_names) << "  writers: " << t.writers.size();
    if (!t.writers.empty()) std::cout << " (" << participants_of(t.writers) << ")";
    std::cout << "  readers: " << t.readers.size();
    if (!t.readers.empty()) std::cout << " (" << participants_of(t.readers) << ")";
    std::cout << "\n";
    if (verbose) print_endpoints(t);
  }
  return 0;
}

int run_info(int argc, char** argv) {
  dds::ParticipantOptions participant;
  bool verbose = false;
  double wait = 2.0;
  std::vector<std::string> args;
  dds::CommandLine cli("macsim_topic info", "The type, writers and readers of one topic.");
  cli.participant_options(&participant);
  cli.arguments("TOPIC", &args);
  cli.flag("v", "verbose: every writer and reader with its QoS", &verbose);
  cli.option("wait", "SECONDS", "how long to listen to discovery (default 2)", &wait);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (args.size() != 1) {
    log::error("macsim_topic info: give one TOPIC");
    return kUsage;
  }
  Session session(participant);
  if (!sleep_for(wait)) return 130;
  const std::string name = dds::dds_topic_name(args[0]);
  auto t = session.graph.topic(name);
  if (!t) {
    std::vector<std::string> names;
    for (const auto& [n, s] : session.graph.topics()) names.push_back(n);
    log::error("macsim_topic info: no topic '{}' on domain {}; topics: {}", name,
               participant.domain, names.empty() ? "none" : join(names));
    return 1;
  }
  std::vector<std::string> type_names;
  for (const auto& type : t->types) type_names.push_back(type_for_people(type) + " (" + type + ")");
  std::cout << "Topic: " << name << "\nType: " << join(type_names)
            << "\nWriter count: " << t->writers.size() << "\nReader count: " << t->readers.size()
            << "\n";
  if (verbose) print_endpoints(*t);
  return 0;
}

// ---- echo / hz / bw
// ------------------------------------------------------------------------------

/// Hands samples from Fast DDS's thread to the verb's thread.
class SampleQueue {
 public:
  void push(topic::ReceivedSample&& s) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.size() >= 1000) {
      queue_.pop_front();  // a slow terminal drops the oldest, never blocks DDS
      ++dropped_;
    }
    queue_.push_back(std::move(s));
    ready_.notify_one();
  }
  std::optional<topic::ReceivedSample> pop(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!ready_.wait_for(lock, timeout, [&] { return !queue_.empty(); })) return std::nullopt;
    auto s = std::move(queue_.front());
    queue_.pop_front();
    return s;
  }
  std::uint64_t dropped() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<topic::ReceivedSample> queue_;
  std::uint64_t dropped_ = 0;
};

topic::RawQos qos_for(const topic::TopicSummary& t, int depth) {
  const auto choice = topic::reader_choice(t);
  topic::RawQos qos;
  qos.reliable = choice.reliable;
  qos.transient_local = choice.transient_local;
  qos.depth = depth;
  return qos;
}

int run_echo(int argc, char** argv) {
  dds::ParticipantOptions participant;
  bool once = false, no_arr = false;
  int count = 0;
  double wait = 5.0, timeout = 0;
  std::string field;
  std::vector<std::string> args;
  dds::CommandLine cli("macsim_topic echo",
                       "Prints each sample of a topic as YAML (as ros2 topic echo), '---' between "
                       "samples.");
  cli.participant_options(&participant);
  cli.arguments("TOPIC", &args);
  cli.flag("once", "print one sample and exit", &once);
  cli.option("count", "N", "exit after N samples", &count);
  cli.option("field", "PATH", "print only this member, e.g. pose.pose.position or ranges.3",
             &field);
  cli.flag("no-arr", "print sequences and arrays as their type and length", &no_arr);
  cli.option("wait", "SECONDS", "how long to wait for a writer of the topic (default 5)", &wait);
  cli.option("timeout", "SECONDS", "exit 1 if no sample came for this long (default: wait on)",
             &timeout);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (args.size() != 1) {
    log::error("macsim_topic echo: give one TOPIC");
    return kUsage;
  }
  if (count < 0 || !(wait > 0) || timeout < 0) {
    log::error("macsim_topic echo: --count, --wait and --timeout must be positive");
    return kUsage;
  }
  if (once) count = 1;
  Session session(participant);
  auto t = find_topic(session, args[0], wait, participant.domain);
  if (!t) return 1;
  auto type = known_type(t->writers.front().type);
  if (!type) return 1;
  topic::YamlStyle style;
  style.no_arrays = no_arr;
  style.field = field;
  SampleQueue queue;
  topic::RawReader reader(*session.participant, t->name, t->writers.front().type, qos_for(*t, 100),
                          [&](topic::ReceivedSample&& s) { queue.push(std::move(s)); });
  int printed = 0;
  auto last = Clock::now();
  while (!g_stop.load() && (count == 0 || printed < count)) {
    auto sample = queue.pop(std::chrono::milliseconds(100));
    if (!sample) {
      if (timeout > 0 && Clock::now() - last > std::chrono::duration<double>(timeout)) {
        log::error("macsim_topic echo: no sample on {} for {:g} s", t->name, timeout);
        return 1;
      }
      continue;
    }
    last = Clock::now();
    try {
      std::cout << topic::sample_to_yaml(sample->bytes, *type, style) << "---\n" << std::flush;
    } catch (const topic::SampleError& e) {
      log::error("macsim_topic echo: {}", e.what());
      if (!field.empty()) return 1;  // a field that does not exist stays so
    }
    ++printed;
  }
  return 0;
}

struct Stats {
  double mean = 0, min = 0, max = 0, std = 0;
};
Stats stats_of(const std::vector<double>& values) {
  Stats s;
  if (values.empty()) return s;
  s.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  s.min = *std::min_element(values.begin(), values.end());
  s.max = *std::max_element(values.begin(), values.end());
  double sq = 0;
  for (double v : values) sq += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(sq / static_cast<double>(values.size()));
  return s;
}

/// hz and bw: receive samples for a while, report rate or bandwidth every second.
int run_timing(int argc, char** argv, bool bandwidth) {
  const char* verb = bandwidth ? "macsim_topic bw" : "macsim_topic hz";
  dds::ParticipantOptions participant;
  int window = bandwidth ? 100 : 10000;
  double wait = 5.0, duration = 0;
  std::vector<std::string> args;
  dds::CommandLine cli(verb, bandwidth ? "Bandwidth of a topic (bytes on the wire per second, "
                                         "message sizes) over a window of samples."
                                       : "Rate of a topic (samples per second, min/max/std of "
                                         "the periods) over a window of samples.");
  cli.participant_options(&participant);
  cli.arguments("TOPIC", &args);
  cli.option(
      "window", "N",
      bandwidth ? "samples in the window (default 100)" : "samples in the window (default 10000)",
      &window);
  cli.option("duration", "SECONDS", "stop after this long and print the final figures", &duration);
  cli.option("wait", "SECONDS", "how long to wait for a writer of the topic (default 5)", &wait);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (args.size() != 1) {
    log::error("{}: give one TOPIC", verb);
    return kUsage;
  }
  if (window < 2 || !(wait > 0) || duration < 0) {
    log::error("{}: --window must be 2 or more, --wait and --duration positive", verb);
    return kUsage;
  }
  Session session(participant);
  auto t = find_topic(session, args[0], wait, participant.domain);
  if (!t) return 1;
  std::mutex mutex;
  std::deque<std::pair<std::int64_t, std::size_t>> samples;  // receive time, size
  std::uint64_t total = 0;
  topic::RawReader reader(*session.participant, t->name, t->writers.front().type, qos_for(*t, 100),
                          [&](topic::ReceivedSample&& s) {
                            std::lock_guard<std::mutex> lock(mutex);
                            samples.emplace_back(s.received_ns, s.bytes.size());
                            if (samples.size() > static_cast<std::size_t>(window)) {
                              samples.pop_front();
                            }
                            ++total;
                          });
  const auto start = Clock::now();
  auto report = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    if (samples.size() < 2) {
      std::cout << "no new messages\n" << std::flush;
      return;
    }
    if (bandwidth) {
      std::vector<double> sizes;
      for (const auto& s : samples) sizes.push_back(static_cast<double>(s.second));
      const double span = static_cast<double>(samples.back().first - samples.front().first) * 1e-9;
      const double sum = std::accumulate(sizes.begin() + 1, sizes.end(), 0.0);
      const Stats st = stats_of(sizes);
      std::printf(
          "%.2f KB/s from %zu messages\n\tMessage size mean: %.2f KB min: %.2f KB max: "
          "%.2f KB\n",
          span > 0 ? sum / span / 1000.0 : 0.0, samples.size(), st.mean / 1000.0, st.min / 1000.0,
          st.max / 1000.0);
    } else {
      std::vector<double> periods;
      for (std::size_t i = 1; i < samples.size(); ++i) {
        periods.push_back(static_cast<double>(samples[i].first - samples[i - 1].first) * 1e-9);
      }
      const Stats st = stats_of(periods);
      std::printf("average rate: %.3f\n\tmin: %.6fs max: %.6fs std dev: %.5fs window: %zu\n",
                  st.mean > 0 ? 1.0 / st.mean : 0.0, st.min, st.max, st.std, samples.size());
    }
    std::fflush(stdout);
  };
  while (!g_stop.load()) {
    if (!sleep_for(1.0)) break;
    report();
    if (duration > 0 && Clock::now() - start >= std::chrono::duration<double>(duration)) break;
  }
  std::printf("%s: %llu samples on %s\n", verb, static_cast<unsigned long long>(total),
              t->name.c_str());
  return 0;
}

// ---- pub ---------------------------------------------------------------------------------------

int run_pub(int argc, char** argv) {
  dds::ParticipantOptions participant;
  double rate = 0, wait = 3.0;
  int times = 0;
  std::vector<std::string> args;
  dds::CommandLine cli("macsim_topic pub",
                       "Publishes a sample given as YAML, once or at a rate, e.g.\n  macsim_topic "
                       "pub /kurt/cmd_vel geometry_msgs/msg/Twist '{linear: {x: 0.2}}' --rate 10 "
                       "--domain 7\nMembers not named are zero (a quaternion's w is 1).\n--domain "
                       "N is required (it may move a robot: never on a domain it was not given).");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.arguments("TOPIC TYPE [YAML]", &args);
  cli.option("rate", "HZ", "publish at this rate until stopped (default: once)", &rate);
  cli.option("times", "N", "publish N times (at --rate, default 10 Hz)", &times);
  cli.option("wait", "SECONDS", "wait this long for a reader before publishing (default 3)", &wait);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (args.size() < 2 || args.size() > 3) {
    log::error("macsim_topic pub: give TOPIC TYPE [YAML] (see --help)");
    return kUsage;
  }
  if (rate < 0 || times < 0 || wait < 0 || (rate > 0 && !std::isfinite(rate))) {
    log::error("macsim_topic pub: --rate, --times and --wait must be positive");
    return kUsage;
  }
  const std::string topic_name = dds::dds_topic_name(args[0]);
  const std::string dds_type = dds::dds_type_name(args[1]);
  auto type = known_type(dds_type);
  if (!type) return kUsage;
  std::vector<std::uint8_t> sample;
  try {
    sample = topic::sample_from_yaml(YAML::Load(args.size() == 3 ? args[2] : "{}"), *type);
  } catch (const YAML::Exception& e) {
    log::error("macsim_topic pub: the YAML does not parse: {}", e.what());
    return kUsage;
  } catch (const topic::SampleError& e) {
    log::error("macsim_topic pub: {}", e.what());
    return kUsage;
  }
  Session session(participant);
  // Another type on the topic is refused whenever discovery shows it, before or after this
  // writer exists (a reader of another type never matches it: it would wait in vain).
  auto other_type = [&]() -> std::optional<std::string> {
    if (auto t = session.graph.topic(topic_name)) {
      for (const auto& type_name : t->types) {
        if (type_name != dds_type) return type_name;
      }
    }
    return std::nullopt;
  };
  auto refuse = [&](const std::string& type_name) {
    log::error("macsim_topic pub: {} carries {}, not {}", topic_name, type_for_people(type_name),
               type_for_people(dds_type));
    return kUsage;
  };
  // readers that want a transient-local writer get one: what discovery shows within 0.3 s
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  topic::RawQos qos;
  qos.reliable = true;
  qos.depth = 10;
  if (auto type_name = other_type()) return refuse(*type_name);
  if (auto t = session.graph.topic(topic_name)) {
    for (const auto& r : t->readers) qos.transient_local = qos.transient_local || r.transient_local;
  }
  topic::RawWriter writer(*session.participant, topic_name, dds_type, qos);
  const auto wait_end = Clock::now() + std::chrono::duration<double>(wait);
  while (writer.matched() == 0 && Clock::now() < wait_end && !g_stop.load()) {
    if (auto type_name = other_type()) return refuse(*type_name);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (writer.matched() == 0) {
    log::warn("macsim_topic pub: no reader of {} after {:g} s; publishing anyway", topic_name,
              wait);
  }
  if (times > 0 && rate == 0) rate = 10;
  const int total = rate > 0 ? times : 1;
  int sent = 0;
  auto next = Clock::now();
  while (!g_stop.load() && (total == 0 || sent < total)) {
    if (!writer.write(sample)) {
      log::error("macsim_topic pub: the write was refused");
      return 1;
    }
    ++sent;
    if (rate == 0) break;
    next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate));
    while (Clock::now() < next && !g_stop.load()) {
      std::this_thread::sleep_for(
          std::min<Clock::duration>(next - Clock::now(), std::chrono::milliseconds(20)));
    }
  }
  writer.wait_acknowledged(std::chrono::seconds(2));
  std::printf("macsim_topic pub: %d sample%s on %s\n", sent, sent == 1 ? "" : "s",
              topic_name.c_str());
  return 0;
}

// ---- record -------------------------------------------------------------------------------------

/// Receives samples on DDS threads and stores them from the recording thread.
class Recorder {
 public:
  /// Bytes received and not yet stored at most (samples, their bookkeeping, the batch being
  /// written: topic::SampleQueue::cost): a disk slower than the topics drops samples (counted
  /// as lost) instead of filling memory.
  static constexpr std::size_t kMaxQueuedBytes = std::size_t{256} << 20;

  explicit Recorder(topic::BagWriter& bag) : bag_(bag), queue_(kMaxQueuedBytes) {}
  void add(dds::Participant& participant, const topic::TopicSummary& t) {
    const std::string ros_name = dds::ros_topic_name(t.name);
    const std::string dds_type = t.writers.front().type;
    std::vector<topic::OfferedQos> offered;
    for (const auto& w : t.writers) offered.push_back({w.reliable, w.transient_local});
    const auto type = topic::wire_type(dds_type);
    const int id = bag_.add_topic(ros_name, dds::ros_type_name(dds_type), offered,
                                  type ? topic::ros2_msg_with_dependencies(*type) : "");
    counts_[t.name] = 0;
    auto* count = &counts_[t.name];
    readers_.push_back(std::make_unique<topic::RawReader>(
        participant, t.name, dds_type, qos_for(t, 0), [this, id, count](topic::ReceivedSample&& s) {
          if (!queue_.push(id, std::move(s))) return;  // counted as dropped
          std::lock_guard<std::mutex> lock(mutex_);
          ++*count;
        }));
  }
  /// Stores what arrived; returns after `slice` with nothing new.
  void drain(std::chrono::milliseconds slice) {
    topic::SampleQueue::Batch batch = queue_.take(slice);
    for (const auto& [id, s] : batch) {
      bag_.write(id, s.received_ns, s.bytes.data(), s.bytes.size());
    }
    if (!batch.empty()) bag_.flush();
    queue_.release(batch);  // counted until written: the batch is in memory until then
  }
  /// Stops receiving (the counts are final), then stores what is still queued.
  void finish() {
    for (const auto& r : readers_) lost_ += r->lost();
    readers_.clear();
    drain(std::chrono::milliseconds(0));
  }
  bool has(const std::string& topic) const { return counts_.count(topic) != 0; }
  std::uint64_t lost() const {
    std::uint64_t n = lost_ + queue_.dropped();
    for (const auto& r : readers_) n += r->lost();
    return n;
  }
  const std::map<std::string, std::uint64_t>& counts() const { return counts_; }

 private:
  topic::BagWriter& bag_;
  topic::SampleQueue queue_;  // over kMaxQueuedBytes: dropped, counted as lost
  std::mutex mutex_;          // guards the counts while readers run
  std::map<std::string, std::uint64_t> counts_;
  std::uint64_t lost_ = 0;
  std::vector<std::unique_ptr<topic::RawReader>> readers_;
};

int run_record(int argc, char** argv) {
  dds::ParticipantOptions participant;
  bool all = false;
  std::string out;
  double duration = 0;
  std::vector<std::string> args;
  dds::CommandLine cli("macsim_topic record",
                       "Records topics into a rosbag2 bag (sqlite3 storage, as ROS 2 Jazzy writes "
                       "it: metadata.yaml and DIR_0.db3 with the CDR samples as received). All "
                       "ROS topics (rt/...) by default, also those that appear later.");
  cli.participant_options(&participant);
  cli.arguments("[-a | TOPIC...]", &args);
  cli.flag("a", "all topics (the default when no TOPIC is given)", &all);
  cli.option("o", "DIR", "the bag directory to create (required)", &out);
  cli.option("duration", "SECONDS", "stop after this long (default: until Ctrl-C)", &duration);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (out.empty()) {
    log::error("macsim_topic record: give the bag directory: -o DIR");
    return kUsage;
  }
  if (duration < 0) {
    log::error("macsim_topic record: --duration must be positive");
    return kUsage;
  }
  if (all && !args.empty()) {
    log::error("macsim_topic record: give -a or topics, not both");
    return kUsage;
  }
  std::set<std::string> wanted;
  for (const auto& a : args) wanted.insert(dds::dds_topic_name(a));
  std::unique_ptr<topic::BagWriter> bag;
  try {
    bag = std::make_unique<topic::BagWriter>(out);
  } catch (const topic::BagError& e) {
    log::error("macsim_topic record: {}", e.what());
    return 1;
  }
  Session session(participant);
  Recorder recorder(*bag);
  const auto start = Clock::now();
  auto last_look = Clock::time_point{};
  while (!g_stop.load()) {
    if (Clock::now() - last_look > std::chrono::milliseconds(200)) {
      last_look = Clock::now();
      for (const auto& [name, t] : session.graph.topics()) {
        if (t.writers.empty() || recorder.has(name) || dds::ros_topic_name(name).empty()) continue;
        if (!wanted.empty() && wanted.count(name) == 0) continue;
        recorder.add(*session.participant, t);
        log::info("macsim_topic record: recording {} ({})", name,
                  dds::ros_type_name(t.writers.front().type));
      }
    }
    recorder.drain(std::chrono::milliseconds(50));
    if (duration > 0 && Clock::now() - start >= std::chrono::duration<double>(duration)) break;
  }
  recorder.finish();
  bag->close();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  for (const auto& [name, n] : recorder.counts()) {
    std::printf("  %s: %llu\n", name.c_str(), static_cast<unsigned long long>(n));
  }
  std::printf(
      "macsim_topic record: %llu messages, %.1f MB in %.1f s (%.1f MB/s) into %s; %llu "
      "reported lost\n",
      static_cast<unsigned long long>(bag->message_count()),
      static_cast<double>(bag->bytes_written()) * 1e-6, seconds,
      static_cast<double>(bag->bytes_written()) * 1e-6 / seconds, bag->database_path().c_str(),
      static_cast<unsigned long long>(recorder.lost()));
  for (const auto& w : wanted) {
    if (!recorder.has(w)) log::warn("macsim_topic record: {} never had a writer", w);
  }
  return 0;
}

// ---- play / bag info
// ------------------------------------------------------------------------------

int run_play(int argc, char** argv) {
  dds::ParticipantOptions participant;
  double rate = 1.0, clock_hz = 0, wait = 1.0;
  bool loop = false, clock = false;
  std::vector<std::string> args;
  dds::CommandLine cli("macsim_topic play",
                       "Replays a rosbag2 bag (sqlite3) with its original timing.\n--domain N is "
                       "required (a replayed command moves a robot: never on a domain it was not "
                       "given).");
  cli.participant_options(&participant, /*domain_required=*/true);
  cli.arguments("BAG_DIR [TOPIC...]", &args);
  cli.option("rate", "FACTOR", "play this many times faster (default 1)", &rate);
  cli.flag("loop", "start again at the end, until stopped", &loop);
  cli.flag("clock", "publish rt/clock from the bag's time (100 Hz) instead of a recorded clock",
           &clock);
  cli.option("clock-rate", "HZ", "rate of --clock (default 100)", &clock_hz);
  cli.option("wait", "SECONDS",
             "wait up to this long for a reader of every topic played before starting "
             "(default 1)",
             &wait);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (args.empty()) {
    log::error("macsim_topic play: give BAG_DIR (and the topics to play, default all)");
    return kUsage;
  }
  const std::set<std::string> only(args.begin() + 1, args.end());
  if (!(rate > 0) || !std::isfinite(rate) || clock_hz < 0 || wait < 0) {
    log::error("macsim_topic play: --rate and --clock-rate must be positive");
    return kUsage;
  }
  if (clock_hz > 0) clock = true;
  if (clock && clock_hz == 0) clock_hz = 100;
  std::unique_ptr<topic::BagReader> bag;
  try {
    bag = std::make_unique<topic::BagReader>(args[0]);
  } catch (const topic::BagError& e) {
    log::error("macsim_topic play: {}", e.what());
    return 1;
  }
  Session session(participant);
  std::map<int, std::unique_ptr<topic::RawWriter>> writers;
  std::set<int> ids;
  for (const auto& name : only) {
    const auto& topics = bag->topics();
    if (std::none_of(topics.begin(), topics.end(), [&](const auto& t) { return t.name == name; })) {
      log::error("macsim_topic play: {} has no topic {}", args[0], name);
      return kUsage;
    }
  }
  for (const auto& t : bag->topics()) {
    if (t.serialization_format != "cdr") continue;
    if (!only.empty() && !only.count(t.name)) continue;
    const std::string topic_name = dds::dds_topic_name(t.name);
    if (clock && topic_name == dds::dds_topic_name("/clock")) continue;
    topic::RawQos qos;
    qos.reliable = t.offered_qos.empty() || t.offered_qos.front().reliable;
    qos.transient_local = !t.offered_qos.empty() && t.offered_qos.front().transient_local;
    // A reliable topic keeps every sample until its readers have it: a slow reader slows the
    // playback down instead of losing samples.
    qos.depth = qos.reliable ? 0 : 100;
    writers[t.id] = std::make_unique<topic::RawWriter>(*session.participant, topic_name,
                                                       dds::dds_type_name(t.type), qos);
    ids.insert(t.id);
  }
  std::unique_ptr<dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType>> clock_writer;
  if (clock) {
    clock_writer = std::make_unique<dds::Writer<rosgraph_msgs::msg::dds_::Clock_PubSubType>>(
        *session.participant, "rt/clock", dds::QosFamily::Sensor);
  }
  // Until every writer has a reader (a topic nobody reads waits the whole time).
  const auto wait_end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(wait));
  auto all_read = [&] {
    return std::all_of(writers.begin(), writers.end(),
                       [](const auto& w) { return w.second->matched() > 0; }) &&
           (!clock_writer || clock_writer->matched() > 0);
  };
  while (Clock::now() < wait_end && !all_read() && !g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::uint64_t sent = 0;
  bool failed = false;
  do {
    const auto start = Clock::now();
    std::int64_t next_clock = bag->start_ns();
    auto publish_clock_until = [&](std::int64_t bag_ns) {
      if (!clock_writer) return;
      while (next_clock <= bag_ns) {
        rosgraph_msgs::msg::dds_::Clock_ c;
        c.clock().sec(static_cast<int32_t>(next_clock / 1000000000LL));
        c.clock().nanosec(static_cast<uint32_t>(next_clock % 1000000000LL));
        clock_writer->write(c);
        next_clock += static_cast<std::int64_t>(1e9 / clock_hz);
      }
    };
    bag->for_each(ids, [&](const topic::BagTopic& t, std::int64_t ns, const std::uint8_t* data,
                           std::size_t size) {
      const auto due = start + std::chrono::nanoseconds(static_cast<std::int64_t>(
                                   static_cast<double>(ns - bag->start_ns()) / rate));
      while (Clock::now() < due) {
        if (g_stop.load()) return false;
        if (clock_writer) {
          const auto elapsed = std::chrono::duration<double>(Clock::now() - start).count();
          publish_clock_until(bag->start_ns() + static_cast<std::int64_t>(elapsed * rate * 1e9));
        }
        std::this_thread::sleep_for(
            std::min<Clock::duration>(due - Clock::now(), std::chrono::milliseconds(5)));
      }
      publish_clock_until(ns);
      // A keep-all writer refuses a sample while its history is full of samples a reader has
      // not acknowledged (each refusal after Fast DDS's 100 ms blocking time): wait for the
      // reader instead of dropping the sample, as long as some reader is still there.
      const std::vector<std::uint8_t> bytes(data, data + size);
      const auto give_up = Clock::now() + std::chrono::seconds(30);
      while (!writers[t.id]->write(bytes)) {
        if (g_stop.load()) return false;
        if (writers[t.id]->matched() == 0 || Clock::now() > give_up) {
          log::error("macsim_topic play: a sample of {} at {} ns was refused for 30 s or its "
                     "readers left; stopping",
                     t.name, ns);
          failed = true;
          return false;
        }
      }
      ++sent;
      return !g_stop.load();
    });
  } while (loop && !g_stop.load());
  // What is written is not yet received: stay until the readers acknowledged every sample.
  for (const auto& t : bag->topics()) {
    const auto w = writers.find(t.id);
    if (w != writers.end() && !w->second->wait_acknowledged(std::chrono::seconds(30))) {
      log::warn("macsim_topic play: a reader of {} did not acknowledge every sample in 30 s",
                t.name);
    }
  }
  std::printf("macsim_topic play: %llu messages from %s\n", static_cast<unsigned long long>(sent),
              bag->database_path().c_str());
  return failed ? 1 : 0;
}

int run_bag(int argc, char** argv) {
  std::vector<std::string> args;
  dds::CommandLine cli("macsim_topic bag", "bag info BAG_DIR: summarises a rosbag2 bag.");
  cli.arguments("info BAG_DIR", &args);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (args.size() != 2 || args[0] != "info") {
    log::error("macsim_topic bag: give: info BAG_DIR");
    return kUsage;
  }
  try {
    topic::BagReader bag(args[1]);
    std::cout << topic::bag_summary(bag);
  } catch (const std::exception& e) {
    log::error("macsim_topic bag info: {}", e.what());
    return 1;
  }
  return 0;
}

// ---- types --------------------------------------------------------------------------------------

void show_type(const topic::WireType& type, int indent, std::set<std::string>& shown) {
  for (const auto& m : type.members) {
    std::cout << std::string(indent, ' ') << topic::display_name(*m.type) << " " << m.name << "\n";
    const topic::WireType* inner = m.type.get();
    while (inner->kind == topic::WireType::Kind::Sequence ||
           inner->kind == topic::WireType::Kind::Array) {
      inner = inner->element.get();
    }
    if (!inner->members.empty()) show_type(*inner, indent + 2, shown);
  }
}

int run_types(int argc, char** argv) {
  std::vector<std::string> args;
  bool msg = false;
  dds::CommandLine cli("macsim_topic types",
                       "Lists the project's IDL types; with a TYPE, shows its members (as ros2 "
                       "interface show).");
  cli.arguments("[TYPE]", &args);
  cli.flag("msg", "print TYPE as a ROS 2 .msg definition", &msg);
  if (auto code = cli.parse(argc, argv)) return *code;
  if (args.size() > 1) {
    log::error("macsim_topic types: give at most one TYPE");
    return kUsage;
  }
  if (args.empty()) {
    for (const auto& n : dds::idl_type_names()) {
      auto t = topic::wire_type(n);
      if (t && t->kind == topic::WireType::Kind::Struct) std::cout << dds::ros_type_name(n) << "\n";
    }
    return 0;
  }
  auto type = known_type(dds::dds_type_name(args[0]));
  if (!type) return 1;
  if (msg) {
    const std::string definition = topic::ros2_msg_definition(*type);
    if (definition.empty()) {
      log::error("macsim_topic types: {} has a union: .msg cannot express it", args[0]);
      return 1;
    }
    std::cout << definition;
    return 0;
  }
  std::set<std::string> shown;
  show_type(*type, 0, shown);
  return 0;
}

const char* kUsageText =
    "usage: macsim_topic VERB [options] [arguments]   (macsim_topic VERB --help for each)\n"
    "Inspects, times, publishes, records and replays the topics of a DDS domain with the types\n"
    "of the project's IDL. Topic names as DDS (rt/kurt/odom) or ROS (/kurt/odom); types as ROS\n"
    "(nav_msgs/msg/Odometry) or DDS (nav_msgs::msg::dds_::Odometry_).\n\n"
    "verbs:\n"
    "  list [-v] [-t]            every topic with its type, writers and readers\n"
    "  info TOPIC [-v]           one topic's type, writers and readers\n"
    "  echo TOPIC                print samples as YAML (--once, --count N, --field a.b, --no-arr)\n"
    "  hz TOPIC                  rate: mean, min/max/std of the periods over a window\n"
    "  bw TOPIC                  bandwidth and message sizes over a window\n"
    "  pub TOPIC TYPE 'YAML'     publish once or at --rate (needs --domain)\n"
    "  record [-a | TOPIC...] -o DIR [--duration S]   record a rosbag2 bag (sqlite3)\n"
    "  play DIR [TOPIC...] [--rate R] [--loop] [--clock]  replay a bag (needs --domain)\n"
    "  bag info DIR              summarise a bag\n"
    "  types [TYPE]              the IDL's types, or one type's members\n\n"
    "common options: --domain N (0..232, default 0; pub and play require it), --profile FILE,\n"
    "--quiet (warnings and errors only), --verbose, --log-timestamps, --help\n";

}  // namespace

int main(int argc, char** argv) {
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  if (argc < 2) {
    std::cerr << kUsageText;
    return kUsage;
  }
  const std::string verb = argv[1];
  if (verb == "--help" || verb == "-h" || verb == "help") {
    std::cout << kUsageText;
    return 0;
  }
  const std::map<std::string, int (*)(int, char**)> verbs = {
      {"list", run_list},
      {"info", run_info},
      {"echo", run_echo},
      {"hz", [](int c, char** v) { return run_timing(c, v, false); }},
      {"bw", [](int c, char** v) { return run_timing(c, v, true); }},
      {"pub", run_pub},
      {"record", run_record},
      {"play", run_play},
      {"bag", run_bag},
      {"types", run_types}};
  auto found = verbs.find(verb);
  if (found == verbs.end()) {
    log::error(
        "macsim_topic: unknown verb '{}' (list, info, echo, hz, bw, pub, record, play, bag, "
        "types; see --help)",
        verb);
    return kUsage;
  }
  try {
    return found->second(argc - 1, argv + 1);
  } catch (const std::exception& e) {
    log::error("macsim_topic {}: {}", verb, e.what());
    return 1;
  }
}
