#include "macsim/dds/command_line.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <iostream>
#include <sstream>

#include "macsim/dds/log.h"

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

/// A usage error whose message is complete (printed after "program: ").
class UsageError : public CLI::ParseError {
 public:
  explicit UsageError(std::string message)
      : CLI::ParseError("UsageError", std::move(message), CLI::ExitCodes::ValidationError) {}
};

/// The old rule: an argument starting with '-' is an option unless it reads as a number.
bool looks_like_option(const std::string& arg) {
  return arg.size() > 1 && arg[0] == '-' && !std::isdigit(static_cast<unsigned char>(arg[1])) &&
         arg[1] != '.';
}

}  // namespace

bool parse_image_size(const std::string& text, int* width, int* height) {
  const auto x = text.find('x');
  if (x == std::string::npos) return false;
  int w = 0, h = 0;
  if (!parse_number(text.substr(0, x), &w) || !parse_number(text.substr(x + 1), &h) || w <= 0 ||
      h <= 0) {
    return false;
  }
  *width = w;
  *height = h;
  return true;
}


struct CommandLine::Impl {
  /// What the usage lists and the argument rewriting needs of each option, in declaration order.
  struct Entry {
    std::string name, value_name, help;
    bool takes_value;
  };

  Impl(std::string program_name, std::string summary_text)
      : program(std::move(program_name)), summary(std::move(summary_text)), app(summary, program) {
    app.set_help_flag();  // our own --help (below), printed in our layout
    app.allow_extras();   // unknown options and stray arguments are named by parse()
    app.formatter_fn([this](const CLI::App*, std::string, CLI::AppFormatMode) { return usage(); });
  }

  const Entry* find(const std::string& name) const {
    for (const auto& e : entries) {
      if (e.name == name) return &e;
    }
    return nullptr;
  }

  /// --name for a long name, -n,--n for a one-letter name (both spellings, as before).
  static std::string cli_names(const std::string& name) {
    return name.size() == 1 ? "-" + name + ",--" + name : "--" + name;
  }

  /// An option with a value; `set` returns false for a bad value. Runs as it is met, so
  /// errors come in the order of the command line.
  void add_value(const std::string& name, const std::string& value_name, const std::string& help,
                 std::function<bool(const std::string&)> set) {
    entries.push_back({name, value_name, help, true});
    const std::string shown = "--" + name + " " + value_name;
    app.add_option(
           cli_names(name),
           [set, shown](const CLI::results_t& values) {
             for (const auto& value : values) {
               if (!set(value)) throw UsageError("bad value '" + value + "' for " + shown);
             }
             return true;
           },
           help)
        ->type_name(value_name)
        ->expected(1)
        ->trigger_on_parse();
  }

  void add_flag(const std::string& name, const std::string& help, std::function<void()> set) {
    entries.push_back({name, "", help, false});
    app.add_flag_callback(cli_names(name), std::move(set), help)->trigger_on_parse();
  }

  /// The options every program has, after its own: the log's level, then --help.
  void finish() {
    if (finished) return;
    finished = true;
    CLI::Option* quiet_option = nullptr;
    CLI::Option* verbose_option = nullptr;
    if (!find("quiet")) {
      add_flag("quiet", "print only warnings and errors on stderr", [this] { quiet = true; });
      quiet_option = app.get_option("--quiet");
    }
    if (!find("verbose")) {
      add_flag("verbose", "print debug messages too", [this] { verbose = true; });
      verbose_option = app.get_option("--verbose");
    }
    if (quiet_option && verbose_option) quiet_option->excludes(verbose_option);
    if (!find("log-timestamps")) {
      add_flag("log-timestamps", "start each message on stderr with the date, time and level",
               [this] { timestamps = true; });
    }
    app.add_flag_callback(
           "-h,--help", [] { throw CLI::CallForHelp(); }, "print this help and exit")
        ->trigger_on_parse();
    entries.push_back({"help", "", "print this help and exit", false});
  }

  std::string usage() const {
    std::ostringstream out;
    out << "usage: " << program << " [options]" << (synopsis.empty() ? "" : " " + synopsis) << "\n"
        << summary << "\n\noptions:\n";
    for (const auto& o : entries) {
      std::string head = "--" + o.name + (o.takes_value ? " " + o.value_name : "");
      out << "  " << head;
      out << std::string(head.size() < 24 ? 24 - head.size() : 1, ' ') << o.help << "\n";
    }
    return out.str();
  }

  std::string program, summary, synopsis;
  CLI::App app;
  std::vector<Entry> entries;
  bool finished = false;
  bool domain_required = false, domain_given = false;
  bool quiet = false, verbose = false, timestamps = false;
  bool takes_arguments = false;
};

CommandLine::CommandLine(std::string program, std::string summary)
    : impl_(std::make_unique<Impl>(std::move(program), std::move(summary))) {}

CommandLine::~CommandLine() = default;

void CommandLine::flag(const std::string& name, const std::string& help, bool* target) {
  impl_->add_flag(name, help, [target] { *target = true; });
}

void CommandLine::option(const std::string& name, const std::string& value_name,
                         const std::string& help, std::string* target) {
  impl_->add_value(name, value_name, help, [target](const std::string& v) {
    *target = v;
    return true;
  });
}

void CommandLine::option(const std::string& name, const std::string& value_name,
                         const std::string& help, double* target) {
  impl_->add_value(name, value_name, help,
                   [target](const std::string& v) { return parse_number(v, target); });
}

void CommandLine::option(const std::string& name, const std::string& value_name,
                         const std::string& help, int* target) {
  impl_->add_value(name, value_name, help,
                   [target](const std::string& v) { return parse_number(v, target); });
}

void CommandLine::size_option(const std::string& name, const std::string& value_name,
                              const std::string& help, int* width, int* height) {
  impl_->add_value(name, value_name, help,
                   [width, height](const std::string& v) { return parse_image_size(v, width, height); });
}

void CommandLine::repeated_option(const std::string& name, const std::string& value_name,
                                  const std::string& help, std::vector<std::string>* target) {
  impl_->add_value(name, value_name, help + " (repeatable)", [target](const std::string& v) {
    target->push_back(v);
    return true;
  });
}

void CommandLine::arguments(const std::string& synopsis, std::vector<std::string>* target) {
  impl_->synopsis = synopsis;
  impl_->takes_arguments = true;
  impl_->app
      .add_option(
          "arguments",
          [target](const CLI::results_t& values) {
            target->insert(target->end(), values.begin(), values.end());
            return true;
          },
          synopsis)
      ->type_name(synopsis)
      ->expected(0, -1)  // any number, none too
      ->allow_extra_args();
}

void CommandLine::participant_options(ParticipantOptions* options, bool domain_required) {
  Impl& impl = *impl_;
  options->name = impl.program;  // discovery shows who is who
  impl.domain_required = domain_required;
  impl.add_value("domain", "N",
                 "DDS domain id, 0.." + std::to_string(kMaxDomainId) +
                     (domain_required ? " (required)" : " (default 0)"),
                 [&impl, options](const std::string& v) {
                   int domain = -1;
                   if (!parse_number(v, &domain) || domain < 0 || domain > kMaxDomainId) {
                     return false;
                   }
                   options->domain = domain;
                   impl.domain_given = true;
                   return true;
                 });
  impl.add_value("profile", "FILE",
                 "Fast DDS XML profile file (default: $FASTRTPS_DEFAULT_PROFILES_FILE, else "
                 "Fast DDS defaults)",
                 [options](const std::string& v) {
                   options->profile_file = v;
                   return true;
                 });
}

std::string CommandLine::usage() const {
  impl_->finish();
  return impl_->app.help();
}

std::optional<int> CommandLine::parse(int argc, char** argv) {
  Impl& impl = *impl_;
  impl.finish();
  const std::string& program = impl.program;
  // The seed's spelling -name becomes --name; an option's value is passed on as it is; the
  // errors CLI11 would word differently are named here first.
  std::vector<std::string> args;
  std::string stopped;  // an error met here: named after those of the arguments before it
  bool options_ended = false;
  for (int i = 1; i < argc && stopped.empty(); ++i) {
    std::string arg = argv[i];
    if (options_ended || !looks_like_option(arg)) {
      args.push_back(arg);
      continue;
    }
    if (arg == "--") {
      if (impl.takes_arguments) {
        options_ended = true;
        args.push_back(arg);
      } else {
        stopped = "unknown option '--' (see --help)";
      }
      continue;
    }
    if (arg.rfind("--", 0) != 0 && impl.find(arg.substr(1, arg.find('=') - 1))) arg = "-" + arg;
    args.push_back(arg);
    if (arg.rfind("--", 0) != 0) continue;  // unknown: named below
    const auto eq = arg.find('=');
    const std::string name = arg.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
    const auto* entry = impl.find(name);
    if (!entry) continue;
    if (!entry->takes_value && eq != std::string::npos) {
      stopped = "option --" + name + " takes no value";
      args.pop_back();
    } else if (entry->takes_value && eq == std::string::npos) {
      if (i + 1 < argc) {
        args.push_back(argv[++i]);
      } else {
        stopped = "option --" + name + " needs a value " + entry->value_name;
        args.pop_back();
      }
    }
  }
  std::reverse(args.begin(), args.end());  // CLI11 reads from the back
  try {
    impl.app.parse(std::move(args));
  } catch (const CLI::CallForHelp&) {
    std::cout << usage();
    return 0;
  } catch (const UsageError& e) {
    log::error("{}: {}", program, e.what());
    return 2;
  } catch (const CLI::ParseError& e) {
    log::error("{}: {} (see --help)", program, e.what());
    return 2;
  }
  for (const std::string& arg : impl.app.remaining()) {
    if (arg == "--") continue;  // CLI11 keeps the end of the options among what it did not use
    log::error("{}: {} '{}' (see --help)", program,
               looks_like_option(arg) ? "unknown option" : "unexpected argument", arg);
    return 2;
  }
  if (!stopped.empty()) {
    log::error("{}: {}", program, stopped);
    return 2;
  }
  if (impl.domain_required && !impl.domain_given) {
    log::error(
        "{}: say on which DDS domain: --domain N (required: it acts on a robot or a "
        "simulation, never on a domain it was not given; see --help)",
        program);
    return 2;
  }
  if (impl.quiet) log::set_level(log::Level::warn);
  if (impl.verbose) log::set_level(log::Level::debug);
  if (impl.timestamps) log::set_timestamps(true);
  return std::nullopt;
}

}  // namespace macsim::dds
