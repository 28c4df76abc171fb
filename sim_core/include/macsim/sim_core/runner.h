// The runner owns the world it runs (gz-sim's SimulationRunner): commands from any thread run at
// one point per step, with the world current when they run; pause, steps on request (lock-step)
// and real-time pacing; a new world is parsed off the simulation thread and swapped in between
// two batches of commands. What belongs to one world (its named snapshots, its generation) goes
// with it.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>
#include <typeindex>
#include <variant>
#include <vector>

#include "macsim/sim_core/command.h"
#include "macsim/sim_core/snapshot_store.h"
#include "macsim/sim_core/world.h"

namespace macsim {

class SessionWriter;
struct RecordedRequest;

/// Runs a command on the simulation thread, with the world current at that moment; true when
/// the command acted on the world (a recorded session keeps it).
using CommandExecutor = std::function<bool(const Command&, World&)>;

/// Runs a request of type R (its command carries it) on the simulation thread; true when it
/// acted on the world.
template <class R>
using RequestExecutor = std::function<bool(const R&, const Command&, World&)>;

/// How a world load ended: the new world runs, or the old one runs on and `error` says why
/// (`code`: BadFile when it cannot be read or built, InvalidArgument when it does not fit).
struct LoadOutcome {
  bool ok = false;
  ErrorCode code = ErrorCode::Ok;
  std::string error;
};

/// The slowest real-time factor the loop runs at: slower would mean waits too long to serve.
inline constexpr double kMinRealTimeFactor = 1e-3;

/// Commands and loads queued and not yet run, at most, by default (RunSettings).
inline constexpr std::size_t kDefaultMaxQueuedCommands = 65536;

/// Wall seconds a step request waits for the robot commands it names, by default (RunSettings).
inline constexpr double kDefaultCommandWait = 2.0;

/// How the loop steps.
struct RunSettings {
  bool paused = false;               ///< no stepping but on request
  double real_time_factor = 1.0;     ///< sim seconds per wall second; 0: as fast as possible
  bool pause_on_instability = true;  ///< pause when a step had to put a body back
  /// A world swapped in by load() whose objects start inside each other (World::overlaps()):
  /// refused (BadFile, naming them) when true; either way the log (log_sink.h) gets one line per
  /// pair.
  bool refuse_overlaps = false;
  /// A world swapped in by load(): what starts deeply inside each other is moved apart first
  /// (part_overlaps(), its lines to the log), unless refused above.
  bool part_overlaps = false;
  /// Commands and loads queued and not yet run at most: push() and load() refuse more.
  std::size_t max_queued_commands = kDefaultMaxQueuedCommands;
  /// Wall seconds a step request waits for a robot command it names (StepRequest::
  /// commands_named) before it is refused.
  double command_wait = kDefaultCommandWait;
};

/// What load() did with a world load.
enum class LoadQueued {
  Yes,          ///< queued: `done` runs once it ends
  LoadRunning,  ///< refused: another load is still on its way (one at a time)
  QueueFull,    ///< refused: the command queue is full (RunSettings::max_queued_commands)
};

/// What run() calls around each step.
struct StepHooks {
  std::function<void()> before_step;       ///< e.g. take every command received so far
  std::function<void(World&)> after_step;  ///< publish what the step produced
  /// A step request ended, by its steps, its condition or a cancel (before its `done`): what
  /// was held back for its end goes out.
  std::function<void(World&)> request_end;
};

/// A controller's request for steps (lock-step): at most `steps` steps, ended early when `until`
/// says so; answered through `done` once the last step's data is out.
struct StepRequest {
  uint64_t steps = 0;
  uint64_t check_every = 1;  ///< `until` is asked after every this many steps (and at the end)
  /// Asked on the simulation thread after the step's hooks: true ends the request there.
  std::function<bool(const World&)> until;
  std::function<void(const World&)> each_step;  ///< after every step's hooks (e.g. hash it)
  bool hold_commands = false;  ///< the robots' last commands do not time out meanwhile
  /// The robots hold_commands holds, comma-separated (empty: every robot).
  std::string hold_robots;
  bool publish_at_end = false;  ///< the hooks need publish only the newest data, at the end
  bool cameras = true;          ///< the hooks render the camera instants within it
  /// The caller's last robot command of each of its writers, written before the request: the
  /// first step waits until each has arrived (or a later one of its writer), and a command of
  /// those writers numbered after it waits for the request's end. Lock-step by contract: the
  /// caller need not wait for DDS to acknowledge its commands.
  std::vector<Sender> commands_named;
  std::function<void(bool completed)> done;  ///< false: a pause cancelled it
  /// A named command did not arrive within RunSettings::command_wait: the request ends before
  /// its first step, told why (naming the writer and the sample) instead of `done`.
  std::function<void(const std::string& why)> refused;
};

/// Owns and runs one world at a time.
class Runner {
 public:
  /// Builds the first world; throws WorldFileError as World does.
  explicit Runner(WorldSpec spec, RunSettings settings = {});
  ~Runner();
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;

  // ---- from any thread -------------------------------------------------------------------
  /// Queues a command; it runs before the next step (or at once while paused). False (and
  /// nothing queued) when the queue is full (RunSettings::max_queued_commands), or when it
  /// carries a request of a type no executor takes (set_executor; said in the log).
  [[nodiscard]] bool push(Command command);
  /// A robot command that arrived and was dropped before the queue (not finite): a step
  /// request naming it waits for it no more.
  void note_arrival(const Sender& sent);
  /// Queues in-process code (a Local command: tests, programs embedding the runner).
  [[nodiscard]] bool push(std::function<void(World&)> local);
  /// Queues a world load: `parse` runs on a thread of its own while the current world runs on;
  /// commands queued after it wait and then run on the new world. The new world must have the
  /// same robots (names and types) as the current one. `done` runs on the simulation thread.
  /// Refused (nothing queued, nothing parsed) while another load is still on its way, or when
  /// the queue is full; a load counts as one command.
  /// A recorded session keeps `recorded` once the new world runs (what `parse` reads).
  [[nodiscard]] LoadQueued load(std::function<WorldSpec()> parse,
                                std::function<void(const LoadOutcome&)> done,
                                Command recorded = {});
  /// What a request refused because the queue is full is told (names the cap and its flag).
  std::string queue_full_message() const;
  /// Blocks until a command can run or `deadline` passes; true if one can.
  bool wait_for_commands(std::chrono::steady_clock::time_point deadline);

  // ---- before run() -----------------------------------------------------------------------
  /// Who runs the requests of type R (a Request; null: nobody, and push() refuses them). The
  /// runner's own (KeepRobotCommands) and Local commands need none.
  template <class R>
  void set_executor(RequestExecutor<R> run) {
    static_assert(std::is_base_of_v<Request, R>, "an executor runs a Request's subclass");
    CommandExecutor erased;
    if (run) {
      erased = [run = std::move(run)](const Command& c, World& world) {
        return run(static_cast<const R&>(*c.request), c, world);  // its type, checked
      };
    }
    set_request_executor(typeid(R), std::move(erased));
  }
  /// Who runs robot commands: the robot interface the simulator's node serves; null: the
  /// world's robot itself (run_robot_command: a replay, a test).
  void set_robot_executor(CommandExecutor executor);
  /// True when a request of this type can be queued: an executor takes it, or it is the
  /// runner's own.
  bool takes(const Request& request) const;
  /// Writes every command that acts on the world from now on, with the step it runs at, and
  /// the state hash every writer->hash_every() steps (and now, unless it goes on with a session
  /// resumed, whose last step may have its commands written: a hash comes before them). Null
  /// stops recording.
  void record(std::shared_ptr<SessionWriter> writer, bool resumed = false);

  // ---- on the simulation thread (in commands, hooks or tests) ----------------------------
  /// Runs one command now (its executor), recording it when it acted on the world.
  bool execute(const Command& command);
  /// Writes the command its executor is running to the session now, before the executor's
  /// reply goes out (the runner then does not write it again): a reply sent is never of a
  /// command a killed run's session lacks.
  void record_now(const Command& command);
  /// Writes a request taken or answered now (after steps_run() steps) to the session being
  /// recorded, if any: on disk before its reply goes out.
  void record_request(const RecordedRequest& request);
  /// Steps this runner has run, over every world it ran (a session's clock).
  uint64_t steps_run() const { return steps_run_; }
  /// Commands run so far from `source` (repeats answered with the reply sent before not counted).
  uint64_t commands_run(CommandSource source) const;
  /// Robot commands dropped because their sender had sent them before a request that put the
  /// world back (Command::sent_before), and they arrived after it.
  uint64_t commands_sent_before_reset() const { return commands_fenced_; }
  /// Robot commands written after a step request that named their writer, and so held until
  /// it ended.
  uint64_t commands_held_for_request() const { return commands_held_; }
  /// Robot commands are dropped, not run, until the next step has run its commands (a step
  /// request cut by a kill goes on with the set-points it had: its client's copies, sent again
  /// before it repeats the request, must not act in its middle).
  void drop_robot_commands_until_next_step() { drop_robot_commands_ = true; }
  /// Said by an executor that answered `command` as a repeat of a request already run (a client
  /// that did not hear its reply in time sent it again): it is not counted as run.
  void answered_repeat(const Command& command);
  /// Runs the queued commands in arrival order, swapping in a parsed world where a load stands
  /// (a load still parsing holds it and everything after it back); returns how many ran.
  std::size_t apply_commands();
  /// apply_commands(), then one fixed step of the world.
  void step();
  /// One step as run() makes it, paused or not and without pacing: the hooks around step(),
  /// then a step a controller requested counted down (and answered after the last one).
  void step(const StepHooks& hooks);
  /// The simulator's loop: steps as the settings say, calling the hooks, until `stop` is set or
  /// the world reaches `last_step` steps.
  void run(const std::atomic<bool>& stop, uint64_t last_step, const StepHooks& hooks);

  /// Stops stepping; a step request still running is cancelled (its `done` gets false), as it
  /// is when a command resets the world's time or another world is swapped in.
  void pause();
  void resume() { settings_.paused = false; }
  /// Sim seconds per wall second (kMinRealTimeFactor or more), or 0 for as fast as possible;
  /// false (and unchanged) otherwise.
  bool set_real_time_factor(double factor);
  /// Steps `steps` more steps even while paused; `done(true)` runs once the last one's
  /// after_step hook has run, `done(false)` if a pause cancels it first. False (and nothing
  /// queued) while another request is still stepping.
  bool request_steps(uint64_t steps, std::function<void(bool completed)> done);
  /// The same for a request that may end on a condition and say how its data goes out.
  bool request_steps(StepRequest request);
  /// True while requested steps remain.
  bool stepping_on_request() const { return requested_steps_ > 0; }
  /// The request being stepped, or nullptr.
  const StepRequest* step_request() const { return requested_steps_ > 0 ? &request_ : nullptr; }
  const RunSettings& settings() const { return settings_; }

  World& world() { return *world_; }
  const World& world() const { return *world_; }
  /// Counts world replacements: ids, snapshots and schedules of an older generation are void.
  uint64_t generation() const { return generation_; }
  /// Where this world and every later one read the files operations name (nullptr: anywhere).
  void set_data_roots(std::shared_ptr<const DataRoots> roots);
  /// Where requests may read files (anywhere until set); lives as long as the runner.
  const DataRoots& data_roots() const { return *data_roots_; }
  /// Objects this world and every later one may hold at most (WorldEditor::set_max_objects).
  void set_max_objects(std::size_t max_objects);
  /// The named snapshots of the current world, within their caps (emptied when it is replaced).
  SnapshotStore& snapshots() { return snapshots_; }

 private:
  /// A warning to sim_core's log (log_sink.h).
  void say(const std::string& warning) const;
  void set_request_executor(std::type_index type, CommandExecutor executor);
  /// The executor of the request's type, or null.
  std::shared_ptr<const CommandExecutor> executor_of(const Request& request) const;
  /// From now on, drops every robot command of these senders numbered at or below theirs.
  void fence(const std::vector<Sender>& sent_before);
  /// True if `command` was sent before a request that put the world back.
  bool fenced(const Command& command) const;
  struct Load {
    std::shared_future<WorldSpec> spec;
    std::function<void(const LoadOutcome&)> done;
    Command recorded;
  };
  using Item = std::variant<Command, Load>;

  /// True if the item at the queue's front may run now (a load only once parsed).
  static bool runnable(const Item& item);
  void replace_world(Load& load);
  /// Before a request's first step: takes commands (the hooks' before_step) until every one it
  /// names has arrived; false (and the request refused) when RunSettings::command_wait passed.
  bool wait_for_named_commands(const StepHooks& hooks);
  /// Notes a robot command's arrival (under mutex_).
  void arrived(const Sender& sent);
  /// The running request's named command of this robot command's writer, if the command was
  /// written after it (it then waits for the request's end).
  bool written_after_request(const Command& command) const;
  void finish_requested_step();
  /// The running step request, if any, ends unfinished (its `done` gets false).
  void cancel_request();
  /// Ends the running request: the hooks' request_end, then its `done`.
  void end_request(bool completed);

  std::unique_ptr<World> world_;
  mutable std::mutex executors_mutex_;  // set_executor() against push() of other threads
  // By the request's type; shared, so that a command runs its executor outside the lock.
  std::map<std::type_index, std::shared_ptr<const CommandExecutor>> request_executors_;
  CommandExecutor robot_executor_;
  std::vector<uint64_t> commands_run_;                  // by CommandSource
  std::map<std::array<uint8_t, 16>, uint64_t> fences_;  // by sender: its last command dropped
  uint64_t commands_fenced_ = 0;
  std::map<std::array<uint8_t, 16>, uint64_t> named_;  // of the running request, by writer
  bool named_arrived_ = false;         // the running request's named commands all came
  std::deque<Command> after_request_;  // written after the running request: run at its end
  uint64_t commands_held_ = 0;
  bool drop_robot_commands_ = false;  // drop_robot_commands_until_next_step()
  std::shared_ptr<SessionWriter> recording_;
  bool recorded_now_ = false;  // the command being run was written by record_now()
  uint64_t steps_run_ = 0;
  std::shared_ptr<const DataRoots> data_roots_ = DataRoots::anywhere();
  uint64_t generation_ = 0;
  SnapshotStore snapshots_;
  std::size_t max_objects_ = bounds::kMaxObjects;
  RunSettings settings_;
  uint64_t requested_steps_ = 0;  // left of request_
  uint64_t steps_since_check_ = 0;
  StepRequest request_;
  const StepHooks* hooks_ = nullptr;  // of the run (or step) under way

  std::mutex mutex_;
  std::condition_variable arrived_;
  std::deque<Item> pending_;
  std::size_t queued_ = 0;        // items queued and not yet run (in pending_ or a batch running)
  const std::size_t max_queued_;  // settings_.max_queued_commands (at least 1), for any thread
  std::map<std::array<uint8_t, 16>, uint64_t> arrived_from_;  // by writer: the last number pushed
  std::vector<std::future<void>> loaders_;                    // parses running or done
  bool loading_ = false;  // a load is queued or parsing (guarded by mutex_)
};

}  // namespace macsim
