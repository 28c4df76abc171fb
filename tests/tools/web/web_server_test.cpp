// macsim_web's server without a browser: WebSocket handshakes over a plain socket; at most
// max_clients at once, the next refused with HTTP 503 naming the cap, a closed one's place free,
// handshakes in flight at once counted too; a client that reads nothing misses frames, but not
// those sent as state.
#include "web_server.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace macsim::web {
namespace {

/// A socket that asked `port` for a WebSocket; what the server answered (up to the body's start).
struct Handshake {
  int fd = -1;
  std::string answer;
  bool sent = false;
  /// Connects and asks; reads the answer now unless `read_later` (then call read()).
  explicit Handshake(int port, bool read_later = false) {
    fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) return;
    const std::string request =
        "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
    sent = ::send(fd, request.data(), request.size(), 0) == static_cast<ssize_t>(request.size());
    if (!read_later) read();
  }
  void read() {
    if (!sent) return;
    timeval limit{5, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
    char buffer[4096];
    while (answer.find("\r\n\r\n") == std::string::npos) {
      const ssize_t got = ::recv(fd, buffer, sizeof buffer, 0);
      if (got <= 0) break;
      answer.append(buffer, static_cast<std::size_t>(got));
    }
    // A refusal's body may come in the next segment.
    if (answer.find(" 503 ") != std::string::npos) {
      const ssize_t got = ::recv(fd, buffer, sizeof buffer, 0);
      if (got > 0) answer.append(buffer, static_cast<std::size_t>(got));
    }
  }
  ~Handshake() { close(); }
  void close() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
  bool accepted() const { return answer.rfind("HTTP/1.1 101", 0) == 0; }
};

bool wait_until(const std::function<bool()>& done) {
  for (int i = 0; i < 500; ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return done();
}

/// A web server of at most two browsers on a page of its own (a folder removed at the end),
/// skipping a client with more than `max_buffered` bytes queued.
struct CappedServer {
  explicit CappedServer(const std::string& prefix, std::size_t max_buffered = 2u << 20)
      : root(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))),
        server(options(root, max_buffered), nullptr, nullptr) {}
  ~CappedServer() { std::filesystem::remove_all(root); }
  static WebServer::Options options(const std::filesystem::path& root, std::size_t max_buffered) {
    std::filesystem::create_directories(root);
    std::ofstream(root / "index.html") << "<html></html>";
    WebServer::Options o;
    o.port = 0;
    o.root = root.string();
    o.max_clients = 2;
    o.max_buffered = max_buffered;
    return o;
  }
  std::filesystem::path root;
  WebServer server;
};

TEST(WebServer, AtMostMaxClientsBrowsersAtOnceTheNextIsRefusedWith503) {
  CappedServer served("macsim_web_test_");
  WebServer& server = served.server;

  Handshake first(server.port()), second(server.port());
  EXPECT_TRUE(first.accepted()) << first.answer;
  EXPECT_TRUE(second.accepted()) << second.answer;
  ASSERT_TRUE(wait_until([&] { return server.clients() == 2; }));
  Handshake third(server.port());
  EXPECT_FALSE(third.accepted());
  EXPECT_EQ(third.answer.rfind("HTTP/1.1 503", 0), 0u) << third.answer;
  EXPECT_NE(third.answer.find("--max-clients"), std::string::npos) << third.answer;
  EXPECT_EQ(server.clients_refused(), 1u);
  EXPECT_EQ(server.clients(), 2u);

  first.close();
  ASSERT_TRUE(wait_until([&] { return server.clients() == 1; }));
  Handshake fourth(server.port());
  EXPECT_TRUE(fourth.accepted()) << fourth.answer;
}

TEST(WebServer, HandshakesInFlightAtOnceCountAgainstTheCap) {
  CappedServer served("macsim_web_test_flight_");
  WebServer& server = served.server;

  // Every request is out before any answer is read: the server validates them while the first
  // ones' 101 answers are still being written, before any is open.
  std::vector<std::unique_ptr<Handshake>> handshakes;
  for (int i = 0; i < 12; ++i) {
    handshakes.push_back(std::make_unique<Handshake>(server.port(), /*read_later=*/true));
    ASSERT_TRUE(handshakes.back()->sent);
  }
  std::size_t accepted = 0, refused = 0;
  for (auto& h : handshakes) {
    h->read();
    if (h->accepted()) ++accepted;
    if (h->answer.rfind("HTTP/1.1 503", 0) == 0) ++refused;
  }
  EXPECT_EQ(accepted, 2u);
  EXPECT_EQ(refused, 10u);
  EXPECT_EQ(server.clients_refused(), 10u);
  ASSERT_TRUE(wait_until([&] { return server.clients() == 2; }));

  // Closed, the accepted ones give their places back, once each: two new ones fit, a third not.
  for (auto& h : handshakes) h->close();
  ASSERT_TRUE(wait_until([&] { return server.clients() == 0; }));
  Handshake again1(server.port()), again2(server.port());
  EXPECT_TRUE(again1.accepted()) << again1.answer;
  EXPECT_TRUE(again2.accepted()) << again2.answer;
  Handshake again3(server.port());
  EXPECT_EQ(again3.answer.rfind("HTTP/1.1 503", 0), 0u) << again3.answer;
}

/// The payloads of the unmasked text frames a server sent on `fd` after its handshake's answer
/// (`after`: bytes read past it), read until `enough` holds of them or 10 s pass.
std::vector<std::string> read_text_frames(
    int fd, std::string after, const std::function<bool(const std::vector<std::string>&)>& enough) {
  std::vector<std::string> frames;
  std::string bytes = std::move(after);
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  timeval limit{0, 200000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
  char buffer[65536];
  while (!enough(frames) && std::chrono::steady_clock::now() < give_up) {
    const ssize_t got = ::recv(fd, buffer, sizeof buffer, 0);
    if (got > 0) bytes.append(buffer, static_cast<std::size_t>(got));
    for (;;) {  // whole frames off the front
      if (bytes.size() < 2) break;
      std::size_t length = static_cast<unsigned char>(bytes[1]) & 0x7f, header = 2;
      if (length == 126 || length == 127) {
        header = length == 126 ? 4 : 10;
        if (bytes.size() < header) break;
        length = 0;
        for (std::size_t i = 2; i < header; ++i)
          length = (length << 8) | static_cast<unsigned char>(bytes[i]);
      }
      if (bytes.size() < header + length) break;
      if ((static_cast<unsigned char>(bytes[0]) & 0x0f) == 0x1)
        frames.push_back(bytes.substr(header, length));
      bytes.erase(0, header + length);
    }
  }
  return frames;
}

TEST(WebServer, AClientThatReadsNothingMissesFramesButNoneSentAsState) {
  // 64 KB queued at most; the client reads nothing until 20 MB were sent, more than the
  // sockets' buffers hold.
  CappedServer served("macsim_web_test_state_", 64u << 10);
  WebServer& server = served.server;
  Handshake client(server.port(), /*read_later=*/true);
  client.read();
  ASSERT_TRUE(client.accepted()) << client.answer;
  ASSERT_TRUE(wait_until([&] { return server.clients() == 1; }));
  const std::string update(100u << 10, 'u');
  for (int round = 0; round < 2; ++round) {
    for (int i = 0; i < 100; ++i) server.broadcast_text(update);
    server.broadcast_state("state " + std::to_string(round));
  }
  ASSERT_TRUE(wait_until([&] { return server.frames_skipped() > 0; }));
  const std::string after = client.answer.substr(client.answer.find("\r\n\r\n") + 4);
  const auto frames = read_text_frames(client.fd, after, [](const std::vector<std::string>& got) {
    return !got.empty() && got.back() == "state 1";
  });
  std::vector<std::string> states;
  std::size_t updates = 0;
  for (const auto& frame : frames) {
    if (frame == update)
      ++updates;
    else
      states.push_back(frame);
  }
  EXPECT_EQ(states, (std::vector<std::string>{"state 0", "state 1"}));
  EXPECT_LT(updates, 200u);  // some were skipped
  EXPECT_GT(updates, 0u);
  EXPECT_EQ(updates + server.frames_skipped(), 200u);
}

}  // namespace
}  // namespace macsim::web
