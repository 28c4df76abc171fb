// Sessions: a runner records every command that reaches its world with the step it ran at and
// the state hash every N steps; a replay from the file alone meets every hash, a changed command
// is found at the first hash after it, and a damaged or other-version file is refused by line.
#include "macsim/sim_core/session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "macsim/sim_core/runner.h"
#include "macsim/sim_core/world_loader.h"
#include "sim_core/named_request.h"
#include "support/child_process.h"
#include "support/world_helpers.h"

namespace macsim {
namespace {

const std::string kWorld = "worlds/small_room.xml";

using test::small_room;

/// A session's header: its world, a hash every `every` steps, overlaps parted or kept.
SessionHeader header(const std::string& world, uint64_t every, bool parted = true) {
  SessionHeader h;
  h.world_file = world;
  h.hash_every = every;
  h.overlaps_parted = parted;
  return h;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

/// 600 steps of the small room: the robot driven, turned and its crane moved at odd steps, a
/// local command between (never recorded); hashes every 50 steps.
uint64_t record(const std::string& path) {
  Runner runner(small_room(), RunSettings{true, 0.0});
  runner.record(std::make_shared<SessionWriter>(path, header(kWorld, 50)));
  for (int step = 0; step < 600; ++step) {
    if (step % 37 == 0) {
      EXPECT_TRUE(runner.push(robot_command("kurt", robot::Twist{0.2 + step * 1e-4, 0.3})));
    }
    if (step == 120) {
      EXPECT_TRUE(runner.push(robot_command("kurt", robot::CraneTarget{0.4, 0.2, 0.05})));
    }
    if (step == 200) {
      EXPECT_TRUE(runner.push([](World&) {}));
    }
    runner.step();
  }
  const uint64_t hash = runner.world().state_hash();
  runner.record(nullptr);
  return hash;
}

ReplayOutcome replay(const Session& session) {
  Runner runner(load_world_file(test::source(session.header.world_file)), RunSettings{true, 0.0});
  // The test's sessions load no other world.
  return replay_session(session, runner,
                        [](const Command&) { return std::function<WorldSpec()>(); });
}

TEST(Session, ARecordedRunReplaysToEveryHash) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  record(path);
  const Session session = read_session(path);
  EXPECT_EQ(session.header.world_file, kWorld);
  EXPECT_EQ(session.steps, 600u);
  EXPECT_EQ(session.hashes.size(), 13u);    // steps 0, 50, ..., 600
  EXPECT_EQ(session.commands.size(), 18u);  // 17 twists and one crane command; not the local one
  EXPECT_EQ(operation_name(session.commands[0].command), "twist");
  ASSERT_TRUE(session.commands[0].command.robot.has_value());
  ASSERT_NE(session.commands[0].command.robot->as<robot::Twist>(), nullptr);
  EXPECT_DOUBLE_EQ(session.commands[0].command.robot->as<robot::Twist>()->angular, 0.3);
  const ReplayOutcome outcome = replay(session);
  EXPECT_TRUE(outcome.equal) << outcome.message;
  EXPECT_EQ(outcome.hashes_checked, 13u);
  EXPECT_EQ(outcome.commands_run, 18u);
  EXPECT_EQ(outcome.steps, 600u);
}

TEST(Session, FilesAreEmbeddedWhenReadAndTheReplayReadsThemFromTheFileAlone) {
  // A world, then another world loaded at step 100 (the room with its red box moved), read
  // from files deleted once recorded.
  test::TempDir dir("macsim_session_");
  const std::string first = dir.path() + "/room.xml", second = dir.path() + "/moved.xml";
  std::string room = read_text(test::source(kWorld));
  write_text(first, room);
  std::string moved = room;
  const std::size_t box = moved.find("<ID>red_box</ID>");
  ASSERT_NE(box, std::string::npos);
  const std::size_t pos = moved.find("<POS>", box) + 5;
  moved.insert(pos, "1");  // x 1X.. m: far across the room
  write_text(second, moved);
  const std::string path = dir.path() + "/run.session";
  {
    auto writer = std::make_shared<SessionWriter>(path, header(first, 50));
    const WatchedFiles watched(
        disk_files(), [&](const std::string& p, const std::string& b) { writer->file(p, b); });
    LoadOptions options;
    options.files = &watched;
    Runner runner(load_world_file(first, options), RunSettings{true, 0.0});
    writer->file(first, room);  // the same bytes again: embedded once
    runner.record(writer);
    for (int step = 0; step < 200; ++step) {
      if (step % 40 == 0) {
        EXPECT_TRUE(runner.push(robot_command("kurt", robot::Twist{0.3, 0.1})));
      }
      if (step == 100) {
        auto load = std::make_shared<LoadWorldRequest>();
        load->file = second;
        Command recorded;
        recorded.source = CommandSource::Simulation;
        recorded.request = load;
        std::optional<LoadOutcome> loaded;
        EXPECT_EQ(runner.load([&] { return load_world_file(second, options); },
                              [&](const LoadOutcome& o) { loaded = o; }, recorded),
                  LoadQueued::Yes);
        while (!loaded) runner.apply_commands();
        EXPECT_TRUE(loaded->ok) << loaded->error;
      }
      runner.step();
    }
    runner.record(nullptr);
  }
  std::remove(first.c_str());
  std::remove(second.c_str());
  const Session session = read_session(path);
  ASSERT_EQ(session.files.size(), 2u);
  EXPECT_EQ(session.files[0].path, first);
  EXPECT_EQ(session.files[0].bytes, room);
  EXPECT_EQ(session.files[0].commands_before, 0u);
  EXPECT_EQ(session.files[1].path, second);
  EXPECT_EQ(session.files[1].bytes, moved);
  EXPECT_EQ(session.files[1].commands_before, 3u);  // twists at steps 0, 40 and 80
  EXPECT_TRUE(session.header.self_contained);
  // Written back as read.
  const std::string again = dir.path() + "/again.session";
  write_session(again, session);
  EXPECT_EQ(read_text(again), read_text(path));
  // Replayed with no file but the session's.
  MemoryFiles files;
  embed_first_files(session, files);
  LoadOptions from_session;
  from_session.files = &files;
  Runner runner(load_world_file(first, from_session), RunSettings{true, 0.0});
  const auto outcome = replay_session(
      session, runner,
      [&](const Command& c) -> std::function<WorldSpec()> {
        const auto* load = c.request_as<LoadWorldRequest>();
        if (!load || load->file.empty()) return {};
        const std::string file = load->file;
        return [file, &from_session] { return load_world_file(file, from_session); };
      },
      &files);
  EXPECT_TRUE(outcome.equal) << outcome.message;
  EXPECT_EQ(outcome.hashes_checked, 5u);
  // The moved box is where the second file put it: that file was read, not the first again.
  const auto red = runner.world().objects().find_object("red_box");
  ASSERT_TRUE(red.has_value());
  EXPECT_GT(runner.world().objects().object_state(*red).value.pose.position.x(), 9.0);
  // An embedded file altered after it was recorded is refused naming its line.
  std::string text = read_text(path);
  const std::size_t line = text.find("\nf ", text.find("\nf ") + 1) + 1;
  const std::size_t last = text.find('\n', line) - 1;
  text[last] = text[last] == '0' ? '1' : '0';
  const std::string altered = dir.path() + "/altered.session";
  write_text(altered, text);
  const int line_number = int(std::count(text.begin(), text.begin() + long(line), '\n')) + 1;
  try {
    read_session(altered);
    ADD_FAILURE() << "an altered embedded file was read";
  } catch (const SessionFileError& e) {
    EXPECT_NE(std::string(e.what()).find(altered + ":" + std::to_string(line_number) +
                                         ": the embedded file '" + second +
                                         "' does not match its checksum"),
              std::string::npos)
        << e.what();
  }
}

TEST(Session, AChangedCommandIsFoundAtTheFirstHashAfterIt) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  record(path);
  Session session = read_session(path);
  RecordedCommand& changed = session.commands[6];  // the twist at step 185
  ASSERT_EQ(operation_name(changed.command), "twist");
  ASSERT_EQ(changed.step, 185u);
  const robot::Twist twist = *changed.command.robot->as<robot::Twist>();
  changed.command.robot = robot::Twist{twist.linear + 0.1, twist.angular};
  write_session(dir.path() + "/changed.session", session);
  const ReplayOutcome outcome = replay(read_session(dir.path() + "/changed.session"));
  EXPECT_FALSE(outcome.equal);
  ASSERT_TRUE(outcome.first_difference.has_value());
  EXPECT_EQ(*outcome.first_difference, 200u) << outcome.message;  // the first hash after 185
  EXPECT_EQ(outcome.last_equal, 150u);
  EXPECT_NE(outcome.recorded_hash, outcome.replayed_hash);
  EXPECT_NE(outcome.message.find("differs at step 200"), std::string::npos) << outcome.message;
  // Unchanged, the same file written back replays equal: the writer loses nothing.
  changed.command.robot = twist;
  write_session(dir.path() + "/same.session", session);
  EXPECT_EQ(read_text(dir.path() + "/same.session"), read_text(path));
}

/// The error read_session throws for `text`, or "" if it reads.
std::string refusal(const std::string& path, const std::string& text) {
  write_text(path, text);
  try {
    read_session(path);
  } catch (const SessionFileError& e) {
    return e.what();
  }
  return "";
}

using test::Named;

// A server's request comes back from the file as its name and bytes; the replay has it read as
// its typed request before it runs, and one the reader cannot read ends the replay, naming it.
TEST(Session, ARecordedRequestRunsAsReadAndOneThatCannotBeReadEndsTheReplayNamingIt) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/requests.session";
  {
    Runner runner(load_world_file(test::source(kWorld)), RunSettings{true, 0.0});
    runner.set_executor<Named>([](const Named&, const Command&, World&) { return true; });
    runner.record(std::make_shared<SessionWriter>(path, header(kWorld, 50)));
    for (int step = 0; step < 100; ++step) {
      if (step == 10 || step == 60) {
        const std::string name = step == 10 ? "set_density" : "add_force";
        EXPECT_TRUE(runner.push(request_command<Named>(CommandSource::Supervisor, name)));
      }
      runner.step();
    }
    runner.record(nullptr);
  }
  const Session session = read_session(path);
  ASSERT_EQ(session.commands.size(), 2u);
  const auto* recorded = session.commands[1].command.request_as<WireRequest>();
  ASSERT_NE(recorded, nullptr);
  EXPECT_EQ(recorded->operation, "add_force");
  EXPECT_EQ(recorded->bytes, (std::vector<uint8_t>{'a', 'd', 'd', '_', 'f', 'o', 'r', 'c', 'e'}));
  const auto no_load = [](const Command&) { return std::function<WorldSpec()>(); };
  std::vector<std::string> ran;
  const auto replay_reading = [&](const RequestReader& read) {
    Runner runner(load_world_file(test::source(kWorld)), RunSettings{true, 0.0});
    runner.set_executor<Named>([&](const Named& q, const Command&, World&) {
      ran.push_back(q.operation);
      return true;
    });
    return replay_session(session, runner, no_load, nullptr, {}, read);
  };
  const auto as_named = [](const Command& c) -> std::shared_ptr<const Request> {
    const auto* wire = c.request_as<WireRequest>();
    return std::make_shared<Named>(std::string(wire->bytes.begin(), wire->bytes.end()));
  };
  const ReplayOutcome read = replay_reading(as_named);
  EXPECT_TRUE(read.equal) << read.message;
  EXPECT_EQ(ran, (std::vector<std::string>{"set_density", "add_force"}));
  ran.clear();
  // A reader that knows only the first: the replay ends at the second, naming it.
  const ReplayOutcome cut = replay_reading([&](const Command& c) {
    return c.request_as<WireRequest>()->operation == "set_density" ? as_named(c) : nullptr;
  });
  EXPECT_FALSE(cut.equal);
  EXPECT_EQ(ran, std::vector<std::string>{"set_density"});
  EXPECT_NE(cut.message.find("command 2 (step 60, supervisor add_force"), std::string::npos)
      << cut.message;
}

TEST(Session, ADamagedOrOtherVersionFileIsRefusedNamingTheLine) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  record(path);
  const std::string good = read_text(path);
  const std::string bad = dir.path() + "/bad.session";
  // Another version.
  std::string other = good;
  other.replace(0, good.find('\n'), "macsim-session 7");
  EXPECT_NE(refusal(bad, other)
                .find(bad + ":1: session format version 7; this macsim reads "
                            "versions 1 to 6"),
            std::string::npos)
      << refusal(bad, other);
  // Cut short: half of it, ending inside a line.
  const std::string half = good.substr(0, good.size() / 2);
  EXPECT_NE(refusal(bad, half).find("cut short"), std::string::npos) << refusal(bad, half);
  // A line whose hash is not hex, on line 10 (the first hash, after a header of 9).
  std::string garbled = good;
  std::size_t at = 0;
  for (int line = 1; line < 10; ++line) at = garbled.find('\n', at) + 1;
  ASSERT_EQ(garbled.substr(at, 2), "h ");
  garbled.replace(garbled.find(' ', at + 2) + 1, 1, "z");
  EXPECT_NE(refusal(bad, garbled).find(bad + ":10: a hash must be 16 hex digits"),
            std::string::npos)
      << refusal(bad, garbled);
  // A line lost: the closing line's counts say so.
  std::string lost = good;
  lost.erase(at, lost.find('\n', at) + 1 - at);
  EXPECT_NE(refusal(bad, lost).find("lines are missing"), std::string::npos) << refusal(bad, lost);
  EXPECT_NE(refusal(bad, "").find("empty"), std::string::npos);
  EXPECT_NE(refusal(bad, "<WORLD/>\n").find(":1: not a macsim session file"), std::string::npos);
  // No header before the records; a value not finite; a seed out of range.
  // Version 1 had no 'overlaps' line: the refusal names only the lines it lacks.
  EXPECT_NE(refusal(bad, "macsim-session 1\nend 0 0 0\n")
                .find(":2: the header needs its 'world', 'seed', 'hash-every' line(s) before"),
            std::string::npos)
      << refusal(bad, "macsim-session 1\nend 0 0 0\n");
  const std::string header = good.substr(0, good.find("\nh 0 ") + 1);
  EXPECT_NE(refusal(bad, header + "c 3 robot twist kurt nan,0.1 -\nend 3 1 0\n")
                .find(":10: a command's values must be finite numbers; got 'nan'"),
            std::string::npos)
      << refusal(bad, header + "c 3 robot twist kurt nan,0.1 -\nend 3 1 0\n");
  std::string seed = good;
  seed.replace(seed.find("seed -1"), 7, "seed 99999999999");
  EXPECT_NE(refusal(bad, seed).find(":3: the seed must be"), std::string::npos)
      << refusal(bad, seed);
  // Version 2 must say whether objects started inside each other were parted.
  std::string no_overlaps = good;
  no_overlaps.erase(no_overlaps.find("overlaps parted\n"), 16);
  EXPECT_NE(refusal(bad, no_overlaps)
                .find(":9: the header needs its 'overlaps' line(s) before any record"),
            std::string::npos)
      << refusal(bad, no_overlaps);
  // Version 4 must give the settings that change results.
  std::string no_settings = good;
  no_settings.erase(no_settings.find("strict 0\n"), 9);
  no_settings.erase(
      no_settings.find("snapshots "),
      no_settings.find('\n', no_settings.find("snapshots ")) + 1 - no_settings.find("snapshots "));
  EXPECT_NE(refusal(bad, no_settings)
                .find(":8: the header needs its 'strict', 'snapshots' line(s) before any record"),
            std::string::npos)
      << refusal(bad, no_settings);
  std::string no_limit = good;
  no_limit.replace(no_limit.find("limits 32"), 9, "limits 0");
  EXPECT_NE(refusal(bad, no_limit).find(":7: each limit must be 1 or more"), std::string::npos)
      << refusal(bad, no_limit);
  // Version 6 must name the wire types its bytes were written with.
  std::string no_types = good;
  no_types.erase(no_types.find("wire-types "), no_types.find('\n', no_types.find("wire-types ")) +
                                                   1 - no_types.find("wire-types "));
  EXPECT_NE(refusal(bad, no_types)
                .find(":9: the header needs its 'wire-types' line(s) before any record"),
            std::string::npos)
      << refusal(bad, no_types);
  std::string odd = good;
  odd.replace(odd.find("overlaps parted"), 15, "overlaps maybe");
  EXPECT_NE(refusal(bad, odd).find(":5: overlaps must be 'parted' or 'kept'; got 'maybe'"),
            std::string::npos)
      << refusal(bad, odd);
  EXPECT_EQ(refusal(bad, good), "");
}

TEST(Session, ACutFileIsReadUpToItsLastWholeRecordWhereverTheKillCutIt) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  record(path);
  const Session whole = read_session(path);
  const std::string good = read_text(path);
  // As a kill leaves it: no closing line, and the last line cut at any byte.
  const std::string body = good.substr(0, good.rfind("end "));
  const std::size_t first_record = good.find("\nh 0 ") + 1;
  const std::string cut_path = dir.path() + "/cut.session";
  const std::size_t first_record_end = good.find('\n', first_record) + 1;
  for (std::size_t cut = first_record_end; cut <= body.size(); cut += 5) {
    write_text(cut_path, body.substr(0, cut));
    EXPECT_NE(refusal(cut_path, body.substr(0, cut)).find("cut short"), std::string::npos);
    const Session s = read_session(cut_path, SessionRead::UpToLastWholeRecord);
    const std::size_t last_line_end = body.rfind('\n', cut - 1) + 1;
    ASSERT_TRUE(s.cut_short);
    EXPECT_EQ(s.whole_bytes, last_line_end) << "cut at byte " << cut;
    // Its records are the whole session's first ones, and it ends at the last one's step.
    ASSERT_LE(s.commands.size(), whole.commands.size());
    ASSERT_LE(s.hashes.size(), whole.hashes.size());
    for (std::size_t i = 0; i < s.hashes.size(); ++i)
      EXPECT_EQ(s.hashes[i].hash, whole.hashes[i].hash);
    uint64_t last = s.hashes.back().step;
    if (!s.commands.empty()) last = std::max(last, s.commands.back().step);
    EXPECT_EQ(s.steps, last);
  }
  // The header alone, or with its first record cut, holds nothing to resume from; a whole
  // session reads with its end.
  for (std::size_t cut : {first_record, first_record + 4}) {
    write_text(cut_path, good.substr(0, cut));
    EXPECT_THROW(read_session(cut_path, SessionRead::UpToLastWholeRecord), SessionFileError);
  }
  const Session ended = read_session(path, SessionRead::UpToLastWholeRecord);
  EXPECT_FALSE(ended.cut_short);
  EXPECT_EQ(ended.steps, 600u);
  EXPECT_EQ(ended.whole_bytes, good.rfind("end "));
}

TEST(Session, ADamagedLineIsRefusedNamingItWhenResumingToo) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  record(path);
  std::string text = read_text(path);
  text = text.substr(0, text.rfind("end "));  // killed
  // The 12th line, a whole line before the last, garbled: not taken for a cut.
  std::size_t at = 0;
  for (int line = 1; line < 12; ++line) at = text.find('\n', at) + 1;
  text.replace(text.find(' ', at) + 1, 1, "x");
  write_text(path, text);
  try {
    read_session(path, SessionRead::UpToLastWholeRecord);
    ADD_FAILURE() << "a damaged line was read";
  } catch (const SessionFileError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":12: "), std::string::npos) << e.what();
  }
}

TEST(Session, AResumedWriterGoesOnFromTheLastWholeRecordAndTheWholeReplays) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  record(path);
  std::string text = read_text(path);
  // Killed in the middle of a line after step 300.
  const std::size_t middle = text.find("\nh 350 ") + 6;
  write_text(path, text.substr(0, middle));
  const Session cut = read_session(path, SessionRead::UpToLastWholeRecord);
  ASSERT_EQ(cut.steps, 333u);  // its last whole record: a twist at step 333
  // Resumed: the cut session run to its end, then on with the writer appending.
  Runner runner(small_room(), RunSettings{true, 0.0});
  const ReplayOutcome outcome =
      replay_session(cut, runner, [](const Command&) { return std::function<WorldSpec()>(); });
  ASSERT_TRUE(outcome.equal) << outcome.message;
  EXPECT_EQ(runner.steps_run(), 333u);
  runner.record(std::make_shared<SessionWriter>(path, cut), /*resumed=*/true);
  RecordedRequest answered{
      runner.steps_run(), RecordedRequest::Kind::Answered, "simulation", {1, 2, 3}};
  runner.record_request(answered);
  for (int step = 333; step < 500; ++step) {
    if (step % 40 == 0) {
      EXPECT_TRUE(runner.push(robot_command("kurt", robot::Twist{0.1, -0.3 + step * 1e-4})));
    }
    runner.step();
  }
  runner.record(nullptr);
  // One whole file again: the first 333 steps as recorded, the rest as resumed.
  const Session resumed = read_session(path);
  EXPECT_EQ(resumed.steps, 500u);
  ASSERT_EQ(resumed.requests.size(), 1u);
  EXPECT_EQ(resumed.requests[0].step, 333u);
  EXPECT_EQ(resumed.requests[0].bytes, answered.bytes);
  EXPECT_EQ(read_text(path).substr(0, cut.whole_bytes), text.substr(0, cut.whole_bytes));
  const ReplayOutcome again = replay(resumed);
  EXPECT_TRUE(again.equal) << again.message;
  EXPECT_EQ(again.steps, 500u);
}

TEST(Session, RequestsTakenAndAnsweredAreWrittenBackAsRead) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  {
    Runner runner(small_room(), RunSettings{true, 0.0});
    runner.record(std::make_shared<SessionWriter>(path, header(kWorld, 50)));
    for (int step = 0; step < 200; ++step) {
      if (step % 30 == 0) {
        runner.record_request(
            {runner.steps_run(), RecordedRequest::Kind::Taken, "simulation", {uint8_t(step), 7}});
      }
      if (step % 45 == 0) {
        EXPECT_TRUE(runner.push(robot_command("kurt", robot::Twist{0.1, 0.2})));
        runner.apply_commands();
        runner.record_request({runner.steps_run(),
                               RecordedRequest::Kind::Answered,
                               "simulation",
                               {uint8_t(step), 9}});
      }
      runner.step();
    }
    runner.record(nullptr);
  }
  const Session session = read_session(path);
  EXPECT_EQ(session.requests.size(), 7u + 5u);
  const std::string again = dir.path() + "/again.session";
  write_session(again, session);
  EXPECT_EQ(read_text(again), read_text(path));
  // Bytes that are no hex, or an unknown kind, are refused naming the line.
  std::string text = read_text(path);
  const std::size_t r = text.find("\nr ") + 1;
  const int line = int(std::count(text.begin(), text.begin() + long(r), '\n')) + 1;
  std::string odd = text;
  odd.replace(odd.find("taken", r), 5, "takan");
  EXPECT_NE(refusal(path, odd).find(":" + std::to_string(line) + ": a request is 'taken' or"),
            std::string::npos)
      << refusal(path, odd);
}

TEST(Session, TheHeaderSaysWhetherOverlapsWerePartedAndAVersion1FileReadsAsKept) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  record(path);
  EXPECT_TRUE(read_session(path).header.overlaps_parted);
  const std::string kept = dir.path() + "/kept.session";
  {
    SessionWriter writer(kept, header(kWorld, 50, false));
    writer.finish(0);
  }
  EXPECT_NE(read_text(kept).find("\noverlaps kept\n"), std::string::npos) << read_text(kept);
  EXPECT_FALSE(read_session(kept).header.overlaps_parted);
  // Version 1 had no such line: macsim did not part them then.
  std::string v1 = read_text(path);
  v1.replace(0, v1.find('\n'), "macsim-session 1");
  v1.erase(v1.find("overlaps parted\n"), v1.find("\nh 0 ") - v1.find("overlaps parted\n") + 1);
  const std::string old = dir.path() + "/v1.session";
  std::ofstream(old, std::ios::binary) << v1;
  const Session session = read_session(old);
  EXPECT_FALSE(session.header.overlaps_parted);
  EXPECT_EQ(session.hashes.size(), read_session(path).hashes.size());
}

// A session names the wire types its bytes were written with, as its recorder gave them; one of
// format 5, before sessions named them, reads as naming none.
TEST(Session, TheHeaderNamesTheWireTypesAndAVersion5FileNamesNone) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/typed.session";
  SessionHeader typed = header(kWorld, 50);
  typed.wire_types = "0123456789abcdef";
  {
    SessionWriter writer(path, typed);
    writer.finish(0);
  }
  EXPECT_NE(read_text(path).find("\nwire-types 0123456789abcdef\n"), std::string::npos)
      << read_text(path);
  EXPECT_EQ(read_session(path).header.wire_types, "0123456789abcdef");
  const std::string untyped = dir.path() + "/untyped.session";
  {
    SessionWriter writer(untyped, header(kWorld, 50));
    writer.finish(0);
  }
  EXPECT_NE(read_text(untyped).find("\nwire-types -\n"), std::string::npos) << read_text(untyped);
  EXPECT_EQ(read_session(untyped).header.wire_types, "");
  // Format 5 had no such line.
  std::string v5 = read_text(path);
  v5.replace(0, v5.find('\n'), "macsim-session 5");
  v5.erase(v5.find("wire-types "),
           v5.find('\n', v5.find("wire-types ")) + 1 - v5.find("wire-types "));
  const std::string old = dir.path() + "/v5.session";
  write_text(old, v5);
  EXPECT_EQ(read_session(old).header.wire_types, "");
  // A version 5 file naming them is refused: the line is not of its format.
  std::string v5_typed = read_text(path);
  v5_typed.replace(0, v5_typed.find('\n'), "macsim-session 5");
  write_text(old, v5_typed);
  EXPECT_THROW(read_session(old), SessionFileError);
}

// A robot command's sender (its writer and sample) is written beside it and read back: a resumed
// simulator knows which samples the killed one took (a step request may name them).
TEST(Session, ARobotCommandsSenderIsWrittenAndReadBack) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/senders.session";
  Command sent = robot_command("kurt", robot::Twist{0.2, 0.1});
  Sender sender;
  for (std::size_t k = 0; k < sender.id.size(); ++k) sender.id[k] = static_cast<uint8_t>(k * 17);
  sender.sequence = 42;
  sent.sent_by = sender;
  {
    SessionWriter writer(path, header(kWorld, 50));
    writer.command(0, sent);
    writer.command(3, robot_command("kurt", robot::Twist{0.0, 0.0}));  // a sender not known
    writer.finish(5);
  }
  const std::string text = read_text(path);
  EXPECT_NE(text.find(" - 00112233445566778899aabbccddeeff:42\n"), std::string::npos) << text;
  const Session session = read_session(path);
  ASSERT_EQ(session.commands.size(), 2u);
  ASSERT_TRUE(session.commands[0].command.sent_by.has_value());
  EXPECT_EQ(session.commands[0].command.sent_by->id, sender.id);
  EXPECT_EQ(session.commands[0].command.sent_by->sequence, 42u);
  EXPECT_FALSE(session.commands[1].command.sent_by.has_value());
  // A sender that is not one, or one in a version 5 file, is refused by line.
  std::string bad_text = text;
  bad_text.replace(bad_text.find("ff:42"), 5, "f:42");
  const std::string bad = dir.path() + "/bad.session";
  write_text(bad, bad_text);
  EXPECT_THROW(read_session(bad), SessionFileError);
  std::string v5 = text;
  v5.replace(0, v5.find('\n'), "macsim-session 5");
  v5.erase(v5.find("wire-types "),
           v5.find('\n', v5.find("wire-types ")) + 1 - v5.find("wire-types "));
  write_text(bad, v5);
  try {
    read_session(bad);
    ADD_FAILURE() << "a version 5 file with a sender was read";
  } catch (const SessionFileError& e) {
    EXPECT_NE(std::string(e.what()).find(bad + ":9: not a session record"), std::string::npos)
        << e.what();
  }
}

// A lock-step controller's step requests that hold the robots' commands run one command a
// step: a run of them is one record, ended by a hash or another command, and reads back as one
// command a step in the order they ran.
TEST(Session, HeldStepsAreOneRecordARunAndReadBackAsOneCommandAStep) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/held.session";
  const Command keep = request_command<KeepRobotCommands>(CommandSource::Simulation);
  std::vector<std::pair<uint64_t, std::string>> ran;  // step, operation
  {
    SessionWriter writer(path, header(kWorld, 100));
    writer.hash(0, 1);
    for (uint64_t step = 0; step < 250; ++step) {
      if (step == 100 || step == 200) writer.hash(step, step);
      Command k = keep;
      if (step >= 150 && step < 200) k.target = "kurt";  // a request holding one robot
      writer.command(step, k);
      ran.emplace_back(step, std::string(operation_name(keep)));
      if (step == 120) {
        writer.command(step, robot_command("kurt", robot::Twist{0.2, 0.0}));
        ran.emplace_back(step, "twist");
      }
    }
    writer.finish(250);
  }
  const std::string text = read_text(path);
  for (const char* run : {"\nk 0 99\n", "\nk 100 120\nc 120 robot twist", "\nk 121 149\n",
                          "\nk 150 199 kurt\n", "\nk 200 249\nend 250 251 3\n"}) {
    EXPECT_NE(text.find(run), std::string::npos) << run << " in\n" << text;
  }
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 19) << text;  // header 9, h 3, k 5, c, end
  const Session session = read_session(path);
  // A run is one record in memory too (a file of a few bytes may name millions of steps).
  EXPECT_EQ(session.commands.size(), 6u);                 // 5 runs and the twist
  std::vector<std::pair<uint64_t, const Command*>> read;  // each step's command, runs unrolled
  for (const auto& r : session.commands) {
    for (uint64_t k = 0; k < r.count(); ++k) read.emplace_back(r.step + k, &r.command);
  }
  ASSERT_EQ(read.size(), ran.size());
  for (std::size_t i = 0; i < ran.size(); ++i) {
    // The twist is kurt's; so are the steps held for kurt alone; the rest held every robot.
    const uint64_t step = read[i].first;
    const bool kurts = ran[i].second == "twist" || (step >= 150 && step < 200);
    EXPECT_EQ(read[i].second->target, kurts ? "kurt" : "") << i;
    EXPECT_EQ(step, ran[i].first) << i;
    EXPECT_EQ(operation_name(*read[i].second), ran[i].second) << i;
  }
  // Written again from what was read, the file is the same.
  const std::string again = dir.path() + "/again.session";
  write_session(again, session);
  EXPECT_EQ(read_text(again), text);
  // A run that ends before it starts, or longer than a run may be, is refused by line.
  for (const auto& [from, to, says] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {"k 121 149", "k 149 121", ":15: a run ends before it starts"},
           {"k 121 149", "k 121 99999999999", ":15: a run of more than 10000000 steps"},
           {"k 121 149", "k 12x 149", ":15: a run's first step must be a whole number"}}) {
    std::string bad_text = text;
    bad_text.replace(bad_text.find(from), from.size(), to);
    const std::string bad = dir.path() + "/bad.session";
    write_text(bad, bad_text);
    try {
      read_session(bad);
      ADD_FAILURE() << to << " was read";
    } catch (const SessionFileError& e) {
      EXPECT_NE(std::string(e.what()).find(bad + says), std::string::npos) << e.what();
    }
  }
}

TEST(Session, ARunOfHeldStepsReplaysToEveryHash) {
  // A step request holding the robot's drive for 1.5 s (past the 0.6 s timeout) between two
  // twists: one k record, replayed step by step.
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/held.session";
  {
    Runner runner(small_room(), RunSettings{true, 0.0});
    runner.record(std::make_shared<SessionWriter>(path, header(kWorld, 500)));
    EXPECT_TRUE(runner.push(robot_command("kurt", robot::Twist{0.3, 0.2})));
    std::atomic<bool> stop{false};
    StepRequest request;
    request.steps = 1500;
    request.hold_commands = true;
    request.hold_robots = "kurt";
    request.done = [&](bool) { stop = true; };
    EXPECT_TRUE(runner.push([&](World&) { runner.request_steps(std::move(request)); }));
    runner.run(stop, 100000, {});
    EXPECT_TRUE(runner.push(robot_command("kurt", robot::Twist{-0.2, 0.0})));
    for (int i = 0; i < 300; ++i) runner.step();
    runner.record(nullptr);
  }
  const Session session = read_session(path);
  // Runs end at the hash lines (every 500 steps).
  EXPECT_NE(read_text(path).find("\nh 500 "), std::string::npos);
  EXPECT_NE(read_text(path).find("\nk 500 999 kurt\n"), std::string::npos) << read_text(path);
  const ReplayOutcome outcome = replay(session);
  EXPECT_TRUE(outcome.equal) << outcome.message;
  EXPECT_EQ(outcome.hashes_checked, 4u);   // steps 0, 500, 1000, 1500
  EXPECT_EQ(outcome.commands_run, 1502u);  // a twist, 1500 held steps, a twist
}

TEST(Session, ARobotCommandOfAnUnknownRobotOrOneItLacksDoesNothing) {
  World world(small_room());
  EXPECT_TRUE(run_robot_command(robot_command("kurt", robot::Twist{0.1, 0.0}), world));
  EXPECT_FALSE(run_robot_command(robot_command("nobody", robot::Twist{0.1, 0.0}), world));
  EXPECT_EQ(describe(robot_command("kurt", robot::CraneTarget{0.5, 0.25, 0.1})),
            "robot crane kurt 0.5 0.25 0.1");
}

// A session names each robot command by its type's name; one it does not know, or numbers that
// do not fit the command, are refused with the line and the name.
TEST(Session, ARobotCommandThatIsNoneOrDoesNotFitIsRefusedNamingIt) {
  test::TempDir dir("macsim_session_");
  const std::string path = dir.path() + "/run.session";
  record(path);
  const std::string text = read_text(path);
  for (const auto& [from, to, says] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {" robot twist kurt ", " robot fly kurt ", "no robot command 'fly'"},
           {" robot crane kurt 0.40000000000000002,", " robot crane kurt ",
            "robot command 'crane' does not take 2 numbers"}}) {
    std::string changed = text;
    const auto at = changed.find(from);
    ASSERT_NE(at, std::string::npos) << from << "\n" << text.substr(0, 400);
    changed.replace(at, from.size(), to);
    const std::string broken = dir.path() + "/broken.session";
    std::ofstream(broken, std::ios::binary) << changed;
    try {
      read_session(broken);
      ADD_FAILURE() << "read: " << to;
    } catch (const SessionFileError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("broken.session:"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace macsim
