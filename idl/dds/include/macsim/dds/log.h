// Leveled diagnostics on stderr, for every MACSim-DDS program: one line per call, formatted
// fmt-style, written through spdlog (kept out of this header).
//
//   macsim::log::info("macsim: loaded {} objects", count);
//   macsim::log::warn("macsim: warning: {}", what);
//   macsim::log::debug("step {} took {:.3f} ms", step, ms);   // shown with --verbose only
//
// The text is printed as given (no level or program name added), so a message reads the same
// as before it went through the log; --log-timestamps puts the time and level before each line.
// The level is set by the command line (macsim/dds/command_line.h): --quiet shows warnings and
// errors only, --verbose adds debug messages. What a program produces (a summary asked for,
// YAML, CSV) goes to stdout, not here.
#pragma once

#include <fmt/core.h>

#include <string_view>
#include <utility>

namespace macsim::log {

enum class Level { debug, info, warn, error, off };

/// The lowest level written (default: info).
void set_level(Level level);
Level level();
bool enabled(Level level);
/// Each line starts with the date, time and level (default: the message alone).
void set_timestamps(bool on);

/// Writes one line at `level` (a newline is added), if that level is enabled.
void write(Level level, std::string_view message);

template <class... Args>
void debug(fmt::format_string<Args...> format, Args&&... args) {
  if (enabled(Level::debug)) write(Level::debug, fmt::format(format, std::forward<Args>(args)...));
}
template <class... Args>
void info(fmt::format_string<Args...> format, Args&&... args) {
  if (enabled(Level::info)) write(Level::info, fmt::format(format, std::forward<Args>(args)...));
}
template <class... Args>
void warn(fmt::format_string<Args...> format, Args&&... args) {
  if (enabled(Level::warn)) write(Level::warn, fmt::format(format, std::forward<Args>(args)...));
}
template <class... Args>
void error(fmt::format_string<Args...> format, Args&&... args) {
  if (enabled(Level::error)) write(Level::error, fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace macsim::log
