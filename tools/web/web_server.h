// A small HTTP + WebSocket server (websocketpp on standalone asio, in a thread of its own):
// static files from one directory, and WebSocket clients the owner broadcasts frames to. A
// client whose send queue is still full misses a frame; nothing queues up behind it, but what a
// later frame does not replace (broadcast_state) reaches every client.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace macsim::web {

/// Serves `root`'s files over HTTP and WebSocket clients on the same port.
class WebServer {
 public:
  struct Options {
    std::string bind = "127.0.0.1";       ///< address to listen on
    int port = 8080;                      ///< 0: any free port (port() says which)
    std::string root;                     ///< directory whose files are served (read at start)
    std::size_t max_buffered = 2u << 20;  ///< bytes queued to a client before frames skip it
    std::size_t max_clients = 16;  ///< WebSocket clients at once; more get HTTP 503 (--max-clients)
  };
  /// A new client: the frames it gets first (text), e.g. the whole scene.
  using OnOpen = std::function<std::vector<std::string>()>;
  /// A text frame from a client; the answer sent back to that client (empty: none).
  using OnMessage = std::function<std::string(const std::string& text)>;

  /// Listens and serves until destroyed; throws std::runtime_error if it cannot listen.
  WebServer(const Options& options, OnOpen on_open, OnMessage on_message);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  /// The port listened on.
  int port() const;
  /// WebSocket clients connected now.
  std::size_t clients() const;
  /// Sends a text (JSON) frame to every client with room in its queue (from any thread).
  void broadcast_text(std::string text);
  /// Sends a text frame to every client however far behind it is (from any thread): for what a
  /// later frame does not replace (the scene, a plan), never dropped.
  void broadcast_state(std::string text);
  /// Sends a binary frame likewise (images).
  void broadcast_binary(std::string bytes);
  /// Frames a client missed so far because it was still busy with earlier ones.
  std::size_t frames_skipped() const;
  /// WebSocket clients refused so far because max_clients were connected.
  std::size_t clients_refused() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The content type of a file served by its extension (text/html, text/javascript, ...).
std::string content_type(const std::string& path);

}  // namespace macsim::web
