// A world plus its command queue: commands from any thread are applied at one point per step.
#pragma once

#include <memory>

#include "macsim/sim_core/command_queue.h"
#include "macsim/sim_core/world.h"

namespace macsim {

/// The world's command queue: changes from any thread, run on the simulation thread between
/// two steps.
using CommandQueue = BasicCommandQueue<World&>;
/// A change to the world.
using Command = CommandQueue::Command;

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
