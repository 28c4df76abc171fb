// The command line every program takes: values, repeated options, arguments, the seed's -name
// spelling, errors naming the option (exit 2), --help (exit 0, stdout), a required domain, and
// the log's level (--quiet, --verbose).
#include "macsim/dds/command_line.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "macsim/dds/log.h"

namespace macsim::test {
namespace {

using dds::CommandLine;

/// What one parse gave: its exit code (none: go on) and what it printed.
struct Parsed {
  std::optional<int> code;
  std::string out, err;
};

Parsed parse(CommandLine& cli, std::initializer_list<std::string> arguments) {
  std::vector<std::string> strings{"prog"};
  strings.insert(strings.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (auto& s : strings) argv.push_back(s.data());
  argv.push_back(nullptr);
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  Parsed parsed;
  parsed.code = cli.parse(static_cast<int>(strings.size()), argv.data());
  parsed.err = testing::internal::GetCapturedStderr();
  parsed.out = testing::internal::GetCapturedStdout();
  return parsed;
}

/// A program's options, as the programs declare them.
struct Program {
  CommandLine cli{"prog", "Does something."};
  std::string world;
  double rate = 1.0;
  int count = 0;
  bool paused = false, v = false;
  int width = 640, height = 480;
  std::vector<std::string> snapshots;

  Program() {
    cli.option("world", "FILE", "the world file", &world);
    cli.option("rate", "HZ", "how often", &rate);
    cli.option("count", "N", "how many", &count);
    cli.flag("paused", "start paused", &paused);
    cli.flag("v", "verbose listing", &v);
    cli.size_option("size", "WxH", "image size", &width, &height);
    cli.repeated_option("snapshot", "MODE:FILE", "a picture", &snapshots);
  }
};

TEST(CommandLine, ReadsValuesInEverySpelling) {
  Program p;
  const auto parsed = parse(p.cli, {"--world", "a.xml", "--rate=2.5", "-count", "7", "--paused",
                                    "-v", "--size", "320x240"});
  EXPECT_FALSE(parsed.code) << parsed.err;
  EXPECT_EQ(p.world, "a.xml");
  EXPECT_EQ(p.rate, 2.5);
  EXPECT_EQ(p.count, 7);
  EXPECT_TRUE(p.paused);
  EXPECT_TRUE(p.v);
  EXPECT_EQ(p.width, 320);
  EXPECT_EQ(p.height, 240);
  EXPECT_EQ(parsed.err, "");
}

TEST(CommandLine, TheSeedsSingleDashSpellingAndNegativeValues) {
  Program p;
  const auto parsed = parse(p.cli, {"-world", "-odd.xml", "-rate=-3", "--count", "-2", "--v"});
  EXPECT_FALSE(parsed.code) << parsed.err;
  EXPECT_EQ(p.world, "-odd.xml");  // a value is taken as it is
  EXPECT_EQ(p.rate, -3.0);
  EXPECT_EQ(p.count, -2);
  EXPECT_TRUE(p.v);
}

TEST(CommandLine, RepeatedOptionsKeepEveryValueOthersTheLast) {
  Program p;
  const auto parsed = parse(p.cli, {"--snapshot", "Follow:a.png", "--world", "a.xml",
                                    "--snapshot=Inside:b.png", "--world", "b.xml"});
  EXPECT_FALSE(parsed.code) << parsed.err;
  EXPECT_EQ(p.snapshots, (std::vector<std::string>{"Follow:a.png", "Inside:b.png"}));
  EXPECT_EQ(p.world, "b.xml");
}

TEST(CommandLine, ArgumentsAmongOptionsNumbersAndAfterTheDoubleDash) {
  Program p;
  std::vector<std::string> arguments;
  p.cli.arguments("TOPIC [VALUE...]", &arguments);
  const auto parsed =
      parse(p.cli, {"/kurt/odom", "--count", "3", "-5", "-", "{x: 1}", "--", "--paused", "-v"});
  EXPECT_FALSE(parsed.code) << parsed.err;
  EXPECT_EQ(arguments,
            (std::vector<std::string>{"/kurt/odom", "-5", "-", "{x: 1}", "--paused", "-v"}));
  EXPECT_EQ(p.count, 3);
  EXPECT_FALSE(p.paused);
  EXPECT_FALSE(p.v);
}

TEST(CommandLine, BadValuesExitTwoNamingTheOption) {
  for (const auto& [args, says] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"--rate", "fast"}, "prog: bad value 'fast' for --rate HZ\n"},
           {{"--rate", "inf"}, "prog: bad value 'inf' for --rate HZ\n"},
           {{"--count", "1.5"}, "prog: bad value '1.5' for --count N\n"},
           {{"-count=x"}, "prog: bad value 'x' for --count N\n"},
           {{"--size", "640"}, "prog: bad value '640' for --size WxH\n"},
           {{"--size", "0x480"}, "prog: bad value '0x480' for --size WxH\n"},
           {{"--size", "64x48x2"}, "prog: bad value '64x48x2' for --size WxH\n"},
           {{"--world"}, "prog: option --world needs a value FILE\n"},
           {{"--paused=yes"}, "prog: option --paused takes no value\n"},
           {{"--bogus"}, "prog: unknown option '--bogus' (see --help)\n"},
           {{"-bogus=1"}, "prog: unknown option '-bogus=1' (see --help)\n"},
           {{"--count", "2", "stray"}, "prog: unexpected argument 'stray' (see --help)\n"},
           {{"--", "x"}, "prog: unknown option '--' (see --help)\n"},
           // the first error in the command line is the one named
           {{"--rate", "x", "--count", "y"}, "prog: bad value 'x' for --rate HZ\n"},
           {{"--bogus", "--world"}, "prog: unknown option '--bogus' (see --help)\n"}}) {
    Program p;
    std::vector<std::string> strings{"prog"};
    strings.insert(strings.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& s : strings) argv.push_back(s.data());
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const auto code = p.cli.parse(static_cast<int>(argv.size()), argv.data());
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
    EXPECT_EQ(code, 2) << args.front();
    EXPECT_EQ(err, says) << args.front();
  }
}

TEST(CommandLine, HelpListsEveryOptionOnStdoutAndExitsZero) {
  for (const std::string help : {"--help", "-h", "-help"}) {
    Program p;
    dds::ParticipantOptions participant;
    p.cli.participant_options(&participant);
    std::vector<std::string> arguments;
    p.cli.arguments("[FILE...]", &arguments);
    const auto parsed = parse(p.cli, {"--count", "2", help, "--bogus"});
    EXPECT_EQ(parsed.code, 0) << help;
    EXPECT_EQ(parsed.err, "");
    EXPECT_EQ(parsed.out, p.cli.usage());
    EXPECT_EQ(parsed.out.rfind("usage: prog [options] [FILE...]\nDoes something.\n\noptions:\n", 0),
              0u)
        << parsed.out;
    for (const char* line :
         {"  --world FILE            the world file\n",
          "  --v                     verbose listing\n", "  --size WxH              image size\n",
          "  --snapshot MODE:FILE    a picture (repeatable)\n",
          "  --domain N              DDS domain id, 0..232 (default 0)\n", "  --profile FILE",
          "  --quiet                 print only warnings and errors on stderr\n",
          "  --verbose               print debug messages too\n", "  --log-timestamps",
          "  --help                  print this help and exit\n"}) {
      EXPECT_NE(parsed.out.find(line), std::string::npos) << line << "\n" << parsed.out;
    }
    EXPECT_EQ(parsed.out.find("--help"), parsed.out.size() - 49);  // the last line
  }
  // an error before --help is named
  Program p;
  EXPECT_EQ(parse(p.cli, {"--rate", "x", "--help"}).code, 2);
}

TEST(CommandLine, ARequiredDomainMustBeGivenAndInRange) {
  {
    CommandLine cli("mover", "Moves a robot.");
    dds::ParticipantOptions participant;
    cli.participant_options(&participant, /*domain_required=*/true);
    const auto parsed = parse(cli, {});
    EXPECT_EQ(parsed.code, 2);
    EXPECT_NE(parsed.err.find("mover: say on which DDS domain: --domain N (required"),
              std::string::npos)
        << parsed.err;
    EXPECT_EQ(participant.name, "mover");
  }
  {
    CommandLine cli("mover", "Moves a robot.");
    dds::ParticipantOptions participant;
    cli.participant_options(&participant, /*domain_required=*/true);
    const auto help = parse(cli, {"--help"});
    EXPECT_EQ(help.code, 0);
    EXPECT_NE(help.out.find("  --domain N              DDS domain id, 0..232 (required)\n"),
              std::string::npos)
        << help.out;
  }
  for (const std::string bad : {"233", "-1", "7x", ""}) {
    CommandLine cli("mover", "Moves a robot.");
    dds::ParticipantOptions participant;
    cli.participant_options(&participant, true);
    const auto parsed = parse(cli, {"--domain", bad});
    EXPECT_EQ(parsed.code, 2) << bad;
    EXPECT_EQ(parsed.err, "mover: bad value '" + bad + "' for --domain N\n");
  }
  CommandLine cli("mover", "Moves a robot.");
  dds::ParticipantOptions participant;
  cli.participant_options(&participant, true);
  const auto parsed = parse(cli, {"-domain", "232", "--profile=p.xml"});
  EXPECT_FALSE(parsed.code) << parsed.err;
  EXPECT_EQ(participant.domain, 232);
  EXPECT_EQ(participant.profile_file, "p.xml");
}

TEST(CommandLine, QuietAndVerboseSetTheLogsLevel) {
  {
    Program p;
    EXPECT_FALSE(parse(p.cli, {}).code);
    EXPECT_EQ(log::level(), log::Level::info);
  }
  {
    Program p;
    EXPECT_FALSE(parse(p.cli, {"--quiet"}).code);
    EXPECT_EQ(log::level(), log::Level::warn);
    testing::internal::CaptureStderr();
    log::info("not {}", "shown");
    log::warn("shown {}", 1);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "shown 1\n");
  }
  {
    Program p;
    EXPECT_FALSE(parse(p.cli, {"-verbose"}).code);
    EXPECT_EQ(log::level(), log::Level::debug);
    testing::internal::CaptureStderr();
    log::debug("step {} took {:.1f} ms", 3, 1.25);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "step 3 took 1.2 ms\n");
  }
  {
    Program p;
    const auto both = parse(p.cli, {"--quiet", "--verbose"});
    EXPECT_EQ(both.code, 2);
    EXPECT_NE(both.err.find("--quiet excludes --verbose"), std::string::npos) << both.err;
  }
  {
    Program p;
    EXPECT_FALSE(parse(p.cli, {"--log-timestamps"}).code);
    testing::internal::CaptureStderr();
    log::error("macsim: {}", "bad");
    const std::string line = testing::internal::GetCapturedStderr();
    EXPECT_NE(line.find(" error macsim: bad\n"), std::string::npos) << line;
    EXPECT_EQ(line.rfind("20", 0), 0u) << line;  // the date first
    log::set_timestamps(false);
  }
  log::set_level(log::Level::info);
}

TEST(CommandLine, AProgramsOwnVerboseOptionWins) {
  CommandLine cli("shm_clean", "Cleans.");
  bool verbose = false;
  cli.flag("verbose", "name every file removed", &verbose);
  const auto help = parse(cli, {"--help"});
  EXPECT_NE(help.out.find("--verbose               name every file removed"), std::string::npos);
  EXPECT_EQ(help.out.find("print debug messages too"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("--quiet"), std::string::npos) << help.out;
  CommandLine again("shm_clean", "Cleans.");
  again.flag("verbose", "name every file removed", &verbose);
  EXPECT_FALSE(parse(again, {"--verbose"}).code);
  EXPECT_TRUE(verbose);
  EXPECT_EQ(log::level(), log::Level::info);
}

}  // namespace
}  // namespace macsim::test
