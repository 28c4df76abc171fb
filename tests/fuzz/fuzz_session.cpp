// Fuzzes the session reader with any bytes: what a damaged, cut or hostile session file may
// hold. It must refuse with SessionFileError (naming a line) or read a session; a session read
// must write back to a file that reads as the same session (text for text). Anything else
// thrown, a crash or a sanitizer report is a finding.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "finding.h"
#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/session.h"
#include "quiet_log.h"

namespace {

using macsim::fuzz::finding;

std::string text_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace macsim;
  static const std::string written = "/tmp/fuzz_session_" + std::to_string(::getpid());
  const std::string input(reinterpret_cast<const char*>(data), size);
  Session session;
  try {
    session = parse_session(input, "input.session");
  } catch (const SessionFileError& e) {
    if (std::string(e.what()).rfind("input.session:", 0) != 0)
      finding(std::string("a refusal that names no line: ") + e.what());
    return 0;
  } catch (const std::exception& e) {
    finding(std::string("the reader threw something else: ") + e.what());
  }
  try {
    write_session(written, session);
    const std::string once = text_of(written);
    const Session again = parse_session(once, written);
    write_session(written, again);
    if (text_of(written) != once) finding("a session read back writes another text");
    if (again.commands.size() != session.commands.size() ||
        again.hashes.size() != session.hashes.size() ||
        again.files.size() != session.files.size() ||
        again.requests.size() != session.requests.size() || again.steps != session.steps) {
      finding("a session written and read back lost records");
    }
  } catch (const std::exception& e) {
    finding(std::string("a session read could not be written back and read: ") + e.what());
  }
  std::remove(written.c_str());
  return 0;
}
