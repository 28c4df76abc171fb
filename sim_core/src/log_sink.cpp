#include "macsim/sim_core/log_sink.h"

#include <spdlog/logger.h>
#include <spdlog/sinks/stdout_sinks.h>

#include <memory>
#include <mutex>

namespace macsim {

namespace {

std::mutex g_mutex;
LogSink g_sink;  // guarded by g_mutex; empty: the default

/// The default: standard error, the message alone, flushed with each line (not in spdlog's
/// registry, so a program's own use of spdlog does not meet it).
void to_stderr(LogLevel level, const std::string& message) {
  static const std::shared_ptr<spdlog::logger> logger = [] {
    auto made = std::make_shared<spdlog::logger>("macsim_sim_core",
                                                 std::make_shared<spdlog::sinks::stderr_sink_mt>());
    made->set_pattern("%v");
    made->set_level(spdlog::level::trace);
    return made;
  }();
  constexpr spdlog::level::level_enum kLevels[] = {spdlog::level::debug, spdlog::level::info,
                                                   spdlog::level::warn, spdlog::level::err};
  logger->log(kLevels[static_cast<int>(level)], message);
}

}  // namespace

LogSink set_log_sink(LogSink sink) {
  std::lock_guard<std::mutex> lock(g_mutex);
  std::swap(g_sink, sink);
  return sink;
}

void log_message(LogLevel level, const std::string& message) {
  LogSink sink;
  {
    std::lock_guard<std::mutex> lock(g_mutex);
    sink = g_sink;  // called outside the lock: a sink may log again, or set another
  }
  if (sink) {
    sink(level, message);
  } else {
    to_stderr(level, message);
  }
}

}  // namespace macsim
