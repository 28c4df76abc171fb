#include "macsim/dds/log.h"

#include <spdlog/logger.h>
#include <spdlog/sinks/stdout_sinks.h>

#include <atomic>
#include <memory>

namespace macsim::log {

namespace {

std::atomic<Level> g_level{Level::info};

spdlog::level::level_enum spdlog_level(Level level) {
  switch (level) {
    case Level::debug:
      return spdlog::level::debug;
    case Level::info:
      return spdlog::level::info;
    case Level::warn:
      return spdlog::level::warn;
    case Level::error:
      return spdlog::level::err;
    case Level::off:
      break;
  }
  return spdlog::level::off;
}

/// The one logger: stderr (flushed after each line), the message alone by default. Not in
/// spdlog's registry, so a program's own use of spdlog does not meet it.
spdlog::logger& logger() {
  static const std::shared_ptr<spdlog::logger> instance = [] {
    auto created = std::make_shared<spdlog::logger>(
        "macsim", std::make_shared<spdlog::sinks::stderr_sink_mt>());
    created->set_pattern("%v");
    created->set_level(spdlog::level::trace);  // the level is checked here, before formatting
    return created;
  }();
  return *instance;
}

}  // namespace

void set_level(Level level) { g_level.store(level); }

Level level() { return g_level.load(); }

bool enabled(Level level) { return level != Level::off && level >= g_level.load(); }

void set_timestamps(bool on) { logger().set_pattern(on ? "%Y-%m-%d %H:%M:%S.%e %-5l %v" : "%v"); }

void write(Level level, std::string_view message) {
  if (!enabled(level)) return;
  logger().log(spdlog_level(level), spdlog::string_view_t(message.data(), message.size()));
}

}  // namespace macsim::log
