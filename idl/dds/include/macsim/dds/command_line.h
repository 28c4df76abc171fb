// The command line every MACSim-DDS program takes (--domain, --profile, --quiet, --verbose,
// --help, ...): options bound to variables, parsed by CLI11 (kept out of this header).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"

namespace macsim::dds {

/// Declares options bound to variables, parses argv, prints usage; errors name the option.
///
/// Options are written --name or, as the seed's programs took them, -name (e.g. -load); a
/// value follows as the next argument or after '=' (--name=value). Every program also takes
/// --quiet (warnings and errors only), --verbose (debug messages too) and --log-timestamps,
/// which set the level of macsim/dds/log.h (a program's own option of one of those names wins).
/// Reads an image size written WxH (e.g. 640x480), both numbers positive; false (and the
/// numbers untouched) otherwise. What size_option() takes.
bool parse_image_size(const std::string& text, int* width, int* height);

class CommandLine {
 public:
  CommandLine(std::string program, std::string summary);
  ~CommandLine();
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  /// A boolean switch, e.g. --paused.
  void flag(const std::string& name, const std::string& help, bool* target);
  /// An option taking a value, e.g. --world FILE.
  void option(const std::string& name, const std::string& value_name, const std::string& help,
              std::string* target);
  void option(const std::string& name, const std::string& value_name, const std::string& help,
              double* target);
  void option(const std::string& name, const std::string& value_name, const std::string& help,
              int* target);
  /// An image size written WxH (e.g. 640x480), both numbers positive.
  void size_option(const std::string& name, const std::string& value_name, const std::string& help,
                   int* width, int* height);
  /// An option that may be given several times; each value is appended.
  void repeated_option(const std::string& name, const std::string& value_name,
                       const std::string& help, std::vector<std::string>* target);
  /// Arguments that are not options (after the options or among them; "--" ends options),
  /// shown in the usage line as `synopsis`. Without this, such an argument is an error.
  void arguments(const std::string& synopsis, std::vector<std::string>* target);
  /// --domain N (0..232) and --profile FILE, bound to the participant options. A program that
  /// moves a robot or changes a simulation passes `domain_required`: without --domain it does
  /// nothing and exits 2 (never acting on a domain it was not given).
  void participant_options(ParticipantOptions* options, bool domain_required = false);

  /// Parses argv. Returns an exit code when the program should stop now: 0 after --help
  /// (printed to stdout), 2 after a usage error (already printed to stderr); std::nullopt to
  /// go on, with the log level set.
  std::optional<int> parse(int argc, char** argv);
  std::string usage() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace macsim::dds
