// macsim_web's server without a browser: WebSocket handshakes over a plain socket; at most
// max_clients at once, the next refused with HTTP 503 naming the cap, a closed one's place free,
// handshakes in flight at once counted too.
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

/// A web server of at most two browsers on a page of its own (a folder removed at the end).
struct CappedServer {
  explicit CappedServer(const std::string& prefix)
      : root(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))),
        server(options(root), nullptr, nullptr) {}
  ~CappedServer() { std::filesystem::remove_all(root); }
  static WebServer::Options options(const std::filesystem::path& root) {
    std::filesystem::create_directories(root);
    std::ofstream(root / "index.html") << "<html></html>";
    WebServer::Options o;
    o.port = 0;
    o.root = root.string();
    o.max_clients = 2;
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

}  // namespace
}  // namespace macsim::web
