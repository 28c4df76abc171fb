// The small command-line parser every MACSim-DDS program uses (--domain, --profile, --help, ...).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "macsim/dds/participant.h"

namespace macsim::dds {

/// Declares options bound to variables, parses argv, prints usage; errors name the option.
class CommandLine {
 public:
  CommandLine(std::string program, std::string summary);

  /// A boolean switch, e.g. --paused.
  void flag(const std::string& name, const std::string& help, bool* target);
  /// An option taking a value, e.g. --world FILE.
  void option(const std::string& name, const std::string& value_name, const std::string& help,
              std::string* target);
  void option(const std::string& name, const std::string& value_name, const std::string& help,
              double* target);
  void option(const std::string& name, const std::string& value_name, const std::string& help,
              int* target);
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

  /// Parses argv. Returns an exit code when the program should stop now: 0 after --help,
  /// 2 after a usage error (already printed to stderr); std::nullopt to go on.
  std::optional<int> parse(int argc, char** argv);
  std::string usage() const;

 private:
  struct Option {
    std::string name, value_name, help;
    std::function<bool(const std::string&)> set;  // false: bad value
    bool takes_value;
  };
  void add(Option option);

  std::string program_, summary_;
  std::vector<Option> options_;
  std::string synopsis_;
  bool domain_required_ = false, domain_given_ = false;
  std::vector<std::string>* arguments_ = nullptr;
};

}  // namespace macsim::dds
