// A world plus its command queue: commands from any thread are applied at one point per step.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "macsim/sim_core/world.h"

namespace macsim {

/// A change to the world, run on the simulation thread between two steps.
using Command = std::function<void(World&)>;

/// Thread-safe FIFO of commands; producers (e.g. DDS callbacks) only push.
class CommandQueue {
 public:
  void push(Command command);
  /// Runs every queued command on `world`, in arrival order; returns how many ran.
  std::size_t drain(World& world);
  /// Blocks until a command is queued or `deadline` passes; true if commands wait.
  bool wait_until(std::chrono::steady_clock::time_point deadline);

 private:
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<Command> pending_;
  std::vector<Command> running_;
};

/// The simulation loop's core: drain the queue once, then step the world once.
class Simulation {
 public:
  explicit Simulation(WorldSpec spec) : world_(std::make_unique<World>(std::move(spec))) {}

  /// Applies the queued commands, then advances one fixed step.
  void step() {
    commands_.drain(*world_);
    world_->step();
  }
  /// Applies the queued commands without stepping (while paused).
  void apply_commands() { commands_.drain(*world_); }
  /// Replaces the world by a new one (built before the old one goes: a bad world changes
  /// nothing). Call on the simulation thread, e.g. from a command.
  void load(WorldSpec spec) { world_ = std::make_unique<World>(std::move(spec)); }

  CommandQueue& commands() { return commands_; }
  World& world() { return *world_; }
  const World& world() const { return *world_; }

 private:
  std::unique_ptr<World> world_;
  CommandQueue commands_;
};

}  // namespace macsim
