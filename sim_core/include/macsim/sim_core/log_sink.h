// sim_core's one voice: every message its libraries have for a person (the loader's warnings,
// the runner's, the renderer's, the viewer's, the session writer's) goes to one sink, set once
// per process. The programs set it to their leveled log (macsim/dds/log.h: --quiet, --verbose,
// --log-timestamps); a test captures it with ScopedLogSink. Without a sink set, messages go to
// standard error through spdlog, one line each. sim_core writes nowhere else.
#pragma once

#include <functional>
#include <string>

namespace macsim {

enum class LogLevel { Debug, Info, Warning, Error };

/// Receives one message (no trailing newline); may be called from any thread.
using LogSink = std::function<void(LogLevel, const std::string&)>;

/// Sets where sim_core's messages go (an empty sink: the default); returns the sink it replaces.
LogSink set_log_sink(LogSink sink);

/// One message to the sink.
void log_message(LogLevel level, const std::string& message);

/// A sink for the life of this object (a test's capture); the one before comes back after it.
class ScopedLogSink {
 public:
  explicit ScopedLogSink(LogSink sink) : previous_(set_log_sink(std::move(sink))) {}
  ~ScopedLogSink() { set_log_sink(std::move(previous_)); }
  ScopedLogSink(const ScopedLogSink&) = delete;
  ScopedLogSink& operator=(const ScopedLogSink&) = delete;

 private:
  LogSink previous_;
};

}  // namespace macsim
