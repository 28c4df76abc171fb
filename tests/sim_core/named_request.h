// A server's request as the runner's and the session's tests make one: its name alone.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "macsim/sim_core/command.h"

namespace macsim::test {

/// A request named NAME whose wire form is its name's bytes.
struct Named final : Request {
  explicit Named(std::string name) : operation(std::move(name)) {}
  std::string operation;
  std::string_view name() const override { return operation; }
  std::vector<uint8_t> wire() const override { return {operation.begin(), operation.end()}; }
};

}  // namespace macsim::test
