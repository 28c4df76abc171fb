#include "macsim/dds/command_line.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

namespace macsim::dds {

namespace {

template <class Number>
bool parse_number(const std::string& text, Number* out) {
  if constexpr (std::is_floating_point_v<Number>) {
    try {
      std::size_t used = 0;
      double value = std::stod(text, &used);
      if (used != text.size() || !std::isfinite(value)) return false;
      *out = value;
      return true;
    } catch (const std::exception&) {
      return false;
    }
  } else {
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, *out);
    return ec == std::errc() && ptr == end && !text.empty();
  }
}

}  // namespace

CommandLine::CommandLine(std::string program, std::string summary)
    : program_(std::move(program)), summary_(std::move(summary)) {}

void CommandLine::add(Option option) { options_.push_back(std::move(option)); }

void CommandLine::flag(const std::string& name, const std::string& help, bool* target) {
  add({name, "", help,
       [target](const std::string&) {
         *target = true;
         return true;
       },
       false});
}

void CommandLine::option(const std::string& name, const std::string& value_name,
                         const std::string& help, std::string* target) {
  add({name, value_name, help,
       [target](const std::string& v) {
         *target = v;
         return true;
       },
       true});
}

void CommandLine::option(const std::string& name, const std::string& value_name,
                         const std::string& help, double* target) {
  add({name, value_name, help, [target](const std::string& v) { return parse_number(v, target); },
       true});
}

void CommandLine::option(const std::string& name, const std::string& value_name,
                         const std::string& help, int* target) {
  add({name, value_name, help, [target](const std::string& v) { return parse_number(v, target); },
       true});
}

void CommandLine::repeated_option(const std::string& name, const std::string& value_name,
                                  const std::string& help, std::vector<std::string>* target) {
  add({name, value_name, help + " (repeatable)",
       [target](const std::string& v) {
         target->push_back(v);
         return true;
       },
       true});
}

void CommandLine::arguments(const std::string& synopsis, std::vector<std::string>* target) {
  synopsis_ = synopsis;
  arguments_ = target;
}

void CommandLine::participant_options(ParticipantOptions* options, bool domain_required) {
  options->name = program_;  // discovery shows who is who
  domain_required_ = domain_required;
  add({"domain", "N",
       "DDS domain id, 0.." + std::to_string(kMaxDomainId) +
           (domain_required ? " (required)" : " (default 0)"),
       [this, options](const std::string& v) {
         int domain = -1;
         if (!parse_number(v, &domain) || domain < 0 || domain > kMaxDomainId) return false;
         options->domain = domain;
         domain_given_ = true;
         return true;
       },
       true});
  add({"profile", "FILE",
       "Fast DDS XML profile file (default: $FASTRTPS_DEFAULT_PROFILES_FILE, else Fast DDS "
       "defaults)",
       [options](const std::string& v) {
         options->profile_file = v;
         return true;
       },
       true});
}

std::string CommandLine::usage() const {
  std::ostringstream out;
  out << "usage: " << program_ << " [options]" << (synopsis_.empty() ? "" : " " + synopsis_) << "\n"
      << summary_ << "\n\noptions:\n";
  for (const auto& o : options_) {
    std::string head = "--" + o.name + (o.takes_value ? " " + o.value_name : "");
    out << "  " << head;
    out << std::string(head.size() < 24 ? 24 - head.size() : 1, ' ') << o.help << "\n";
  }
  out << "  --help                  print this help and exit\n";
  return out.str();
}

std::optional<int> CommandLine::parse(int argc, char** argv) {
  bool options_ended = false;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (!options_ended && (arg == "--help" || arg == "-h" || arg == "-help")) {
      std::cout << usage();
      return 0;
    }
    if (arguments_ && !options_ended && arg == "--") {
      options_ended = true;
      continue;
    }
    const bool is_option =
        arg.size() > 1 && arg[0] == '-' && !std::isdigit(arg[1]) && arg[1] != '.';
    if (arguments_ && (options_ended || !is_option)) {
      arguments_->push_back(arg);
      continue;
    }
    // Accept --name, -name (the seed's style, e.g. -load) and --name=value.
    std::string name = arg;
    if (name.rfind("--", 0) == 0) {
      name = name.substr(2);
    } else if (name.rfind("-", 0) == 0 && name.size() > 1) {
      name = name.substr(1);
    } else {
      std::cerr << program_ << ": unexpected argument '" << arg << "' (see --help)\n";
      return 2;
    }
    std::optional<std::string> value;
    if (auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    const Option* match = nullptr;
    for (const auto& o : options_) {
      if (o.name == name) match = &o;
    }
    if (!match) {
      std::cerr << program_ << ": unknown option '" << arg << "' (see --help)\n";
      return 2;
    }
    if (match->takes_value && !value) {
      if (i + 1 >= argc) {
        std::cerr << program_ << ": option --" << name << " needs a value " << match->value_name
                  << "\n";
        return 2;
      }
      value = argv[++i];
    }
    if (!match->takes_value && value) {
      std::cerr << program_ << ": option --" << name << " takes no value\n";
      return 2;
    }
    if (!match->set(value.value_or(""))) {
      std::cerr << program_ << ": bad value '" << *value << "' for --" << name << " "
                << match->value_name << "\n";
      return 2;
    }
  }
  if (domain_required_ && !domain_given_) {
    std::cerr << program_
              << ": say on which DDS domain: --domain N (required: it acts on a robot "
                 "or a simulation, never on a domain it was not given; see --help)\n";
    return 2;
  }
  return std::nullopt;
}

}  // namespace macsim::dds
