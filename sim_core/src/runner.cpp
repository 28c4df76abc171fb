#include "macsim/sim_core/runner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/session.h"
#include "macsim/sim_core/world_loader.h"

namespace macsim {

using Clock = std::chrono::steady_clock;

namespace {
/// Senders whose commands before a reset are remembered at most (beyond: one forgotten per new
/// one).
constexpr std::size_t kMaxFences = 4096;

/// Notes `sent` in a map of the highest number seen by sender, at most kMaxFences senders (one
/// forgotten per new one beyond).
void keep_highest(std::map<std::array<uint8_t, 16>, uint64_t>& highest, const Sender& sent) {
  if (highest.size() >= kMaxFences && !highest.count(sent.id)) highest.erase(highest.begin());
  uint64_t& last = highest[sent.id];
  last = std::max(last, sent.sequence);
}

/// A writer's GUID as Fast DDS prints it: the participant's prefix, then the entity.
std::string guid_text(const std::array<uint8_t, 16>& id) {
  std::string text;
  char byte[4];
  for (std::size_t k = 0; k < id.size(); ++k) {
    std::snprintf(byte, sizeof byte, "%02x", id[k]);
    text += (k == 0 ? "" : k == 12 ? "|" : ".") + std::string(byte);
  }
  return text;
}
}  // namespace

Runner::Runner(WorldSpec spec, RunSettings settings)
    : world_(std::make_unique<World>(std::move(spec))),
      settings_(settings),
      max_queued_(std::max<std::size_t>(settings.max_queued_commands, 1)) {
  commands_run_.resize(kCommandSources, 0);
}

void Runner::set_request_executor(std::type_index type, CommandExecutor executor) {
  std::lock_guard<std::mutex> lock(executors_mutex_);
  if (executor) {
    request_executors_[type] = std::make_shared<const CommandExecutor>(std::move(executor));
  } else {
    request_executors_.erase(type);
  }
}

void Runner::set_robot_executor(CommandExecutor executor) {
  std::lock_guard<std::mutex> lock(executors_mutex_);
  robot_executor_ = std::move(executor);
}

std::shared_ptr<const CommandExecutor> Runner::executor_of(const Request& request) const {
  std::lock_guard<std::mutex> lock(executors_mutex_);
  const auto found = request_executors_.find(typeid(request));
  return found == request_executors_.end() ? nullptr : found->second;
}

bool Runner::takes(const Request& request) const {
  return dynamic_cast<const KeepRobotCommands*>(&request) || executor_of(request) != nullptr;
}

void Runner::record(std::shared_ptr<SessionWriter> writer, bool resumed) {
  if (recording_ && recording_ != writer) recording_->finish(steps_run_);
  recording_ = std::move(writer);
  if (recording_ && !resumed) recording_->hash(steps_run_, world_->state_hash());
}

void Runner::record_now(const Command& command) {
  if (recording_ && !recorded_now_) recording_->command(steps_run_, command);
  recorded_now_ = true;
}

void Runner::record_request(const RecordedRequest& request) {
  if (recording_) recording_->request(steps_run_, request);
}

uint64_t Runner::commands_run(CommandSource source) const {
  return commands_run_[static_cast<std::size_t>(source)];
}

void Runner::answered_repeat(const Command& command) {
  auto& count = commands_run_[static_cast<std::size_t>(command.source)];
  if (count > 0) --count;
}

void Runner::fence(const std::vector<Sender>& sent_before) {
  for (const Sender& s : sent_before) keep_highest(fences_, s);
}

bool Runner::fenced(const Command& command) const {
  if (!command.sent_by) return false;
  const auto fence = fences_.find(command.sent_by->id);
  return fence != fences_.end() && command.sent_by->sequence <= fence->second;
}

bool Runner::execute(const Command& command) {
  if (fenced(command)) {  // sent before a reset, delivered after it: it never acts
    ++commands_fenced_;
    return false;
  }
  if (drop_robot_commands_ && command.source == CommandSource::Robot) return false;
  ++commands_run_[static_cast<std::size_t>(command.source)];
  bool acted = false;
  recorded_now_ = false;
  switch (command.source) {
    case CommandSource::Local:
      if (command.local) command.local(*world_);
      return false;  // code, not a value: never recorded
    case CommandSource::Robot: {
      // The robot interface that serves the robot when one is set (the simulator's bridge),
      // else the world's robot itself (a replay, a test).
      CommandExecutor run;
      {
        std::lock_guard<std::mutex> lock(executors_mutex_);
        run = robot_executor_;
      }
      acted = run ? run(command, *world_) : run_robot_command(command, *world_);
      if (!acted) {
        log_message(
            LogLevel::Warning,
            "robot command refused: " + (world_->robot(command.target)
                                             ? "robot '" + command.target + "' has no command '" +
                                                   std::string(operation_name(command)) + "'"
                                             : "no robot '" + command.target + "'"));
      }
      break;
    }
    default:
      if (command.request_as<KeepRobotCommands>()) {
        world_->keep_robot_commands(command.target);
        acted = true;
        break;
      }
      if (const auto run = command.request ? executor_of(*command.request) : nullptr) {
        acted = (*run)(command, *world_);
      } else {
        say("macsim: nobody runs " + describe(command) + "; dropped");
      }
  }
  if (acted && !command.sent_before.empty()) fence(command.sent_before);
  if (acted && recording_ && !recorded_now_) recording_->command(steps_run_, command);
  recorded_now_ = false;
  return acted;
}

void Runner::set_data_roots(std::shared_ptr<const DataRoots> roots) {
  data_roots_ = roots ? std::move(roots) : DataRoots::anywhere();
  world_->set_data_roots(data_roots_);
}

void Runner::set_max_objects(std::size_t max_objects) {
  max_objects_ = max_objects;
  world_->edit().set_max_objects(max_objects);
}

Runner::~Runner() {
  if (recording_) recording_->finish(steps_run_);  // however the run ended
  std::vector<std::future<void>> loaders;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    loaders.swap(loaders_);
  }
  for (auto& loader : loaders) loader.wait();  // a parse still running finishes first
}

bool Runner::push(std::function<void(World&)> local) {
  Command command;
  command.local = std::move(local);
  return push(std::move(command));
}

void Runner::note_arrival(const Sender& sent) {
  std::lock_guard<std::mutex> lock(mutex_);
  arrived(sent);
}

void Runner::arrived(const Sender& sent) { keep_highest(arrived_from_, sent); }

bool Runner::push(Command command) {
  if (command.request && !takes(*command.request)) {  // refused by its type, before the queue
    log_message(LogLevel::Error, "macsim: refused " + describe(command) +
                                     ": no executor takes a request of its type");
    return false;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // Arrived, even when refused below: a step request waits no more.
    if (command.sent_by) arrived(*command.sent_by);
    if (queued_ >= max_queued_) return false;
    pending_.emplace_back(std::move(command));
    ++queued_;
  }
  arrived_.notify_one();
  return true;
}

std::string Runner::queue_full_message() const {
  return "the simulator's command queue is full: at most " + std::to_string(max_queued_) +
         " requests and robot commands wait for the simulation thread (macsim "
         "--max-queued-commands N); ask again once it has served them";
}

LoadQueued Runner::load(std::function<WorldSpec()> parse,
                        std::function<void(const LoadOutcome&)> done, Command recorded) {
  auto promise = std::make_shared<std::promise<WorldSpec>>();
  std::shared_future<WorldSpec> spec = promise->get_future().share();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (loading_) return LoadQueued::LoadRunning;
    if (queued_ >= max_queued_) return LoadQueued::QueueFull;
    std::erase_if(loaders_, [](const std::future<void>& f) {
      return f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
    });
    // Parsed on a thread of its own; when done it wakes the loop, so a paused runner swaps at once.
    try {
      loaders_.push_back(std::async(std::launch::async, [this, promise, parse = std::move(parse)] {
        try {
          promise->set_value(parse());
        } catch (...) {
          promise->set_exception(std::current_exception());
        }
        { std::lock_guard<std::mutex> wake(mutex_); }
        arrived_.notify_all();
      }));
    } catch (const std::system_error&) {
      return LoadQueued::LoadRunning;  // no thread to be had: refused like a second load
    }
    loading_ = true;
    pending_.emplace_back(Load{std::move(spec), std::move(done), std::move(recorded)});
    ++queued_;
  }
  arrived_.notify_one();
  return LoadQueued::Yes;
}

bool Runner::runnable(const Item& item) {
  const Load* load = std::get_if<Load>(&item);
  return !load || load->spec.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

bool Runner::wait_for_commands(Clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  return arrived_.wait_until(lock, deadline,
                             [this] { return !pending_.empty() && runnable(pending_.front()); });
}

std::size_t Runner::apply_commands() {
  std::size_t ran = 0;
  for (;;) {  // one batch per pass: up to and including a parsed load
    std::size_t ran_now = 0;
    std::deque<Item> batch;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      batch.swap(pending_);
    }
    while (!batch.empty()) {
      if (!runnable(batch.front())) break;
      Item item = std::move(batch.front());
      batch.pop_front();
      if (auto* command = std::get_if<Command>(&item)) {
        if (written_after_request(*command)) {  // acts once the request it came after ended
          after_request_.push_back(std::move(*command));
          ++commands_held_;
          ++ran_now;
          continue;
        }
        try {
          execute(*command);
        } catch (const std::exception& e) {  // a command's own errors are its replies
          say(std::string("macsim: a command failed and was dropped: ") + e.what());
        }
        ++ran_now;
        continue;
      }
      replace_world(std::get<Load>(item));
      ++ran_now;
      break;  // the world changed: the rest is the next batch
    }
    ran += ran_now;
    const bool more = !batch.empty() && runnable(batch.front());
    {
      std::lock_guard<std::mutex> lock(mutex_);  // what was held back goes first again
      queued_ -= ran_now;  // counted until now: a batch running holds its place in the queue
      pending_.insert(pending_.begin(), std::make_move_iterator(batch.begin()),
                      std::make_move_iterator(batch.end()));
    }
    if (!more) return ran;
  }
}

void Runner::replace_world(Load& load) {
  LoadOutcome outcome;
  try {
    WorldSpec spec = load.spec.get();
    // The robots' topics are served for the whole run: the same robots, by name and type.
    std::vector<std::pair<std::string, std::string>> now, next;
    for (const auto& r : world_->robots()) now.emplace_back(r->name(), r->spec().type);
    for (const auto& r : spec.robots) next.emplace_back(r.name, r.type);
    if (now != next) {
      outcome.code = ErrorCode::InvalidArgument;
      outcome.error = "the new world must have the same robots (names and types) as this one";
    } else {
      if (settings_.part_overlaps && !settings_.refuse_overlaps) {
        for (const auto& line : part_overlaps(spec)) log_message(LogLevel::Warning, line);
      }
      auto world = std::make_unique<World>(std::move(spec));  // a bad world changes nothing
      admit_overlaps(*world, settings_.refuse_overlaps);
      world->set_data_roots(data_roots_);
      world->edit().set_max_objects(max_objects_);
      world_ = std::move(world);
      ++generation_;
      snapshots_.clear();
      outcome.ok = true;
      fence(load.recorded.sent_before);
      if (recording_ && load.recorded.request) recording_->command(steps_run_, load.recorded);
    }
  } catch (const WorldFileError& e) {
    outcome.code = ErrorCode::BadFile;
    outcome.error = e.what();
  } catch (const FileRefused& e) {
    outcome.code = ErrorCode::BadFile;
    outcome.error = e.what();
  } catch (const std::exception& e) {
    outcome.code = ErrorCode::BadFile;
    outcome.error = std::string("cannot load the world: ") + e.what();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    loading_ = false;
  }
  if (load.done) load.done(outcome);
}

void Runner::step() {
  const bool requested = requested_steps_ > 0;
  const double before = world_->time();
  const uint64_t generation = generation_;
  apply_commands();
  drop_robot_commands_ = false;
  // A request does not run on into a reset that took the time back or into another world: its
  // conditions and samples were about the world it started in.
  if (requested_steps_ > 0 && (generation_ != generation || world_->time() < before)) {
    cancel_request();
  }
  // A request cancelled by what just ran (a pause, a reset, another world) gets no more steps.
  if (requested && requested_steps_ == 0 && settings_.paused) return;
  // A body gone non-finite or wild was put back and reported (an Instability event naming it);
  // pausing keeps a learning run from stepping on through a broken world unnoticed.
  const bool stable = world_->step();
  ++steps_run_;
  if (recording_ && steps_run_ % recording_->hash_every() == 0)
    recording_->hash(steps_run_, world_->state_hash());
  if (!stable && settings_.pause_on_instability) pause();
}

bool Runner::written_after_request(const Command& command) const {
  if (requested_steps_ == 0 || !command.sent_by) return false;
  const auto named = named_.find(command.sent_by->id);
  return named != named_.end() && command.sent_by->sequence > named->second;
}

bool Runner::wait_for_named_commands(const StepHooks& hooks) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(settings_.command_wait));
  for (;;) {
    std::optional<Sender> missing;
    uint64_t had = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& named : named_) {
        const auto arrived = arrived_from_.find(named.first);
        if (arrived == arrived_from_.end() || arrived->second < named.second) {
          missing = Sender{named.first, named.second};
          had = arrived == arrived_from_.end() ? 0 : arrived->second;
          break;
        }
      }
    }
    if (!missing) {
      named_arrived_ = true;
      return true;
    }
    if (Clock::now() >= deadline) {
      char waited[32];
      std::snprintf(waited, sizeof waited, "%g", settings_.command_wait);
      const std::string why =
          "refused: robot command " + std::to_string(missing->sequence) + " of writer " +
          guid_text(missing->id) +
          ", named by the step request (commands_sent), did not arrive within " + waited +
          " s (macsim --command-wait); " +
          (had ? "the last of that writer was " + std::to_string(had)
               : "none of that writer arrived");
      say("macsim: a step request was " + why);
      auto refused = std::move(request_.refused);
      auto done = std::move(request_.done);
      requested_steps_ = 0;
      request_ = {};
      named_.clear();
      named_arrived_ = false;
      if (refused) {
        refused(why);
      } else if (done) {
        done(false);
      }
      return false;
    }
    // Robot commands come in where the hooks take them: again, a moment later.
    std::this_thread::sleep_for(std::chrono::microseconds(50));
    if (hooks.before_step) hooks.before_step();
  }
}

void Runner::step(const StepHooks& hooks) {
  const StepHooks* outer = hooks_;
  hooks_ = &hooks;  // a request ended inside (by its steps or cancelled) calls its request_end
  if (hooks.before_step) hooks.before_step();
  if (requested_steps_ > 0 && !named_arrived_ && !wait_for_named_commands(hooks)) {
    hooks_ = outer;
    return;
  }
  if (requested_steps_ > 0 && request_.hold_commands) {
    Command keep = request_command<KeepRobotCommands>(CommandSource::Simulation);
    keep.target = request_.hold_robots;
    execute(keep);
  }
  step();
  if (hooks.after_step) hooks.after_step(*world_);
  finish_requested_step();  // a requested step is done once its data is out
  hooks_ = outer;
}

bool Runner::set_real_time_factor(double factor) {
  if (!std::isfinite(factor) || (factor != 0 && factor < kMinRealTimeFactor)) return false;
  settings_.real_time_factor = factor;
  return true;
}

void Runner::pause() {
  settings_.paused = true;
  cancel_request();  // a huge request can be stopped
}

void Runner::cancel_request() {
  if (requested_steps_ > 0) end_request(false);
}

void Runner::end_request(bool completed) {
  requested_steps_ = 0;
  // What the hooks held back for the request's end goes out before its answer.
  if (hooks_ && hooks_->request_end) hooks_->request_end(*world_);
  auto done = std::move(request_.done);
  request_ = {};
  named_.clear();
  named_arrived_ = false;
  if (!after_request_.empty()) {  // commands written after it run first, before what came later
    std::lock_guard<std::mutex> lock(mutex_);
    queued_ += after_request_.size();
    pending_.insert(pending_.begin(), std::make_move_iterator(after_request_.begin()),
                    std::make_move_iterator(after_request_.end()));
    after_request_.clear();
  }
  if (done) done(completed);
}

bool Runner::request_steps(uint64_t steps, std::function<void(bool)> done) {
  StepRequest request;
  request.steps = steps;
  request.done = std::move(done);
  return request_steps(std::move(request));
}

bool Runner::request_steps(StepRequest request) {
  if (requested_steps_ > 0) return false;
  if (request.steps == 0) {
    if (request.done) request.done(true);
    return true;
  }
  request.check_every = std::max<uint64_t>(request.check_every, 1);
  requested_steps_ = request.steps;
  steps_since_check_ = 0;
  named_.clear();
  for (const Sender& s : request.commands_named) {
    uint64_t& n = named_[s.id];
    n = std::max(n, s.sequence);
  }
  named_arrived_ = named_.empty();
  request_ = std::move(request);
  return true;
}

void Runner::finish_requested_step() {
  if (requested_steps_ == 0) return;
  --requested_steps_;
  if (request_.each_step) request_.each_step(*world_);
  bool ended = requested_steps_ == 0;
  if (++steps_since_check_ == request_.check_every || ended) {
    steps_since_check_ = 0;
    if (request_.until && request_.until(*world_)) ended = true;
  }
  if (ended) end_request(true);
}

void Runner::run(const std::atomic<bool>& stop, uint64_t last_step, const StepHooks& hooks) {
  hooks_ = &hooks;  // also for a request a command cancels between steps
  auto next = Clock::now();
  while (!stop.load() && world_->steps() < last_step) {
    if (settings_.paused && requested_steps_ == 0) {
      // Requests are served as they come (between steps), not on a polling tick.
      if (wait_for_commands(Clock::now() + std::chrono::milliseconds(50))) apply_commands();
      next = Clock::now();
      continue;
    }
    step(hooks);
    const double pace = settings_.real_time_factor;
    // Steps on request are paced by the requests, not by the clock.
    if (pace > 0 && !settings_.paused && requested_steps_ == 0) {
      next += std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(world_->step_size() / pace));
      const auto now = Clock::now();
      if (now > next + std::chrono::milliseconds(100)) next = now;  // fell behind: no burst
      // Until the next step is due, serve requests as they come (between steps), looking at
      // `stop` at least every 50 ms.
      while (!stop.load() && Clock::now() < next) {
        if (!wait_for_commands(std::min(next, Clock::now() + std::chrono::milliseconds(50))))
          continue;
        apply_commands();
        if (requested_steps_ > 0) break;  // a step request: go now
      }
    }
  }
  hooks_ = nullptr;
}

void Runner::say(const std::string& warning) const { log_message(LogLevel::Warning, warning); }

}  // namespace macsim
