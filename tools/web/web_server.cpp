// websocketpp 0.8.2 needs C++17 (its headers do not compile as C++20 with g++ 12): this file
// is built in a target of its own at C++17; its header shows none of it.
#include "web_server.h"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace macsim::web {

namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;

/// Every regular file under `root`, by its URL path ("/index.html", "/node_modules/...").
std::map<std::string, std::string> read_files(const std::string& root) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(root)) throw std::runtime_error("no such directory to serve: " + root);
  std::map<std::string, std::string> files;
  for (const auto& entry :
       fs::recursive_directory_iterator(root, fs::directory_options::follow_directory_symlink)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::ostringstream content;
    content << in.rdbuf();
    files["/" + fs::relative(entry.path(), root).generic_string()] = content.str();
  }
  return files;
}

}  // namespace

std::string content_type(const std::string& path) {
  static const std::map<std::string, std::string> types{{".html", "text/html; charset=utf-8"},
                                                        {".js", "text/javascript; charset=utf-8"},
                                                        {".mjs", "text/javascript; charset=utf-8"},
                                                        {".css", "text/css; charset=utf-8"},
                                                        {".json", "application/json"},
                                                        {".png", "image/png"},
                                                        {".svg", "image/svg+xml"},
                                                        {".map", "application/json"}};
  const auto dot = path.rfind('.');
  if (dot != std::string::npos) {
    auto type = types.find(path.substr(dot));
    if (type != types.end()) return type->second;
  }
  return "application/octet-stream";
}

struct WebServer::Impl {
  Server server;
  std::map<std::string, std::string> files;
  // Both touched on the server's thread only. A handshake takes its slot when validated (its
  // 101 answer is written later, asynchronously) and gives it back on close or fail: the cap
  // counts handshakes in flight too.
  std::set<Handle, std::owner_less<Handle>> slots;
  std::set<Handle, std::owner_less<Handle>> connections;  // open: the ones frames go to
  std::atomic<std::size_t> count{0};
  std::size_t max_buffered = 0;
  std::size_t max_clients = 0;
  std::atomic<std::size_t> refused{0};
  OnOpen on_open;
  OnMessage on_message;
  std::thread thread;
  int port = 0;

  std::atomic<std::size_t> skipped{0};

  void send_all(const std::string& payload, websocketpp::frame::opcode::value opcode,
                bool may_drop = true) {
    for (const Handle& handle : connections) {
      websocketpp::lib::error_code error;
      auto connection = server.get_con_from_hdl(handle, error);
      if (error) continue;
      if (may_drop && connection->get_buffered_amount() > max_buffered) {
        ++skipped;  // still sending the last ones: this frame is late for it, drop it
        continue;
      }
      connection->send(payload, opcode);
    }
  }
};

WebServer::WebServer(const Options& options, OnOpen on_open, OnMessage on_message)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.files = read_files(options.root);
  s.max_buffered = options.max_buffered;
  s.max_clients = options.max_clients;
  s.on_open = std::move(on_open);
  s.on_message = std::move(on_message);
  s.server.clear_access_channels(websocketpp::log::alevel::all);
  s.server.clear_error_channels(websocketpp::log::elevel::all);
  s.server.init_asio();
  s.server.set_reuse_addr(true);
  s.server.set_http_handler([&s](Handle handle) {
    auto connection = s.server.get_con_from_hdl(handle);
    std::string path = connection->get_resource();
    path = path.substr(0, path.find_first_of("?#"));
    if (path == "/") path = "/index.html";
    auto file = s.files.find(path);
    if (file == s.files.end() || connection->get_request().get_method() != "GET") {
      connection->set_status(file == s.files.end()
                                 ? websocketpp::http::status_code::not_found
                                 : websocketpp::http::status_code::method_not_allowed);
      connection->append_header("Content-Type", "text/plain; charset=utf-8");
      connection->set_body(file == s.files.end() ? "not found: " + path + "\n"
                                                 : "only GET is served\n");
      return;
    }
    connection->set_status(websocketpp::http::status_code::ok);
    connection->append_header("Content-Type", content_type(path));
    connection->append_header("Cache-Control", "no-cache");
    connection->set_body(file->second);
  });
  s.server.set_validate_handler([&s](Handle handle) {  // a WebSocket handshake, before open
    if (s.slots.size() < s.max_clients) {
      s.slots.insert(handle);
      return true;
    }
    ++s.refused;
    auto connection = s.server.get_con_from_hdl(handle);
    connection->set_status(websocketpp::http::status_code::service_unavailable);
    connection->append_header("Content-Type", "text/plain; charset=utf-8");
    connection->set_body(std::to_string(s.max_clients) +
                         " browsers are connected, the cap (macsim_web --max-clients); close one "
                         "and reload\n");
    return false;
  });
  s.server.set_open_handler([&s](Handle handle) {
    s.connections.insert(handle);
    s.count = s.connections.size();
    if (!s.on_open) return;
    for (const std::string& frame : s.on_open()) {
      websocketpp::lib::error_code error;
      s.server.send(handle, frame, websocketpp::frame::opcode::text, error);
    }
  });
  // Every handshake validated ends in exactly one of them (a refused one, or one failed before
  // validation, holds no slot: erasing it changes nothing).
  auto forget = [&s](Handle handle) {
    s.slots.erase(handle);
    s.connections.erase(handle);
    s.count = s.connections.size();
  };
  s.server.set_close_handler(forget);
  s.server.set_fail_handler(forget);
  s.server.set_message_handler([&s](Handle handle, Server::message_ptr message) {
    std::string answer;
    if (message->get_opcode() != websocketpp::frame::opcode::text) {
      answer = R"({"type":"error","message":"only text (JSON) messages are understood"})";
    } else if (s.on_message) {
      answer = s.on_message(message->get_payload());
    }
    if (answer.empty()) return;
    websocketpp::lib::error_code error;
    s.server.send(handle, answer, websocketpp::frame::opcode::text, error);
  });
  websocketpp::lib::error_code error;
  const auto address = asio::ip::make_address(options.bind, error);
  if (error) throw std::runtime_error("--bind: not an IP address: " + options.bind);
  s.server.listen(asio::ip::tcp::endpoint(address, static_cast<unsigned short>(options.port)),
                  error);
  if (error) {
    throw std::runtime_error("cannot listen on " + options.bind + ":" +
                             std::to_string(options.port) + ": " + error.message());
  }
  s.server.start_accept(error);
  if (error) throw std::runtime_error("cannot accept connections: " + error.message());
  s.port = s.server.get_local_endpoint(error).port();
  s.thread = std::thread([&s] { s.server.run(); });
}

WebServer::~WebServer() {
  Impl& s = *impl_;
  asio::post(s.server.get_io_service(), [&s] {
    websocketpp::lib::error_code error;
    s.server.stop_listening(error);
    for (const Handle& handle : s.connections)
      s.server.close(handle, websocketpp::close::status::going_away, "server stops", error);
  });
  // Give the closing handshakes a moment, then stop whatever is left.
  for (int i = 0; i < 50 && s.count > 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  s.server.stop();
  if (s.thread.joinable()) s.thread.join();
}

int WebServer::port() const { return impl_->port; }

std::size_t WebServer::clients() const { return impl_->count; }

std::size_t WebServer::clients_refused() const { return impl_->refused; }

void WebServer::broadcast_text(std::string text) {
  Impl& s = *impl_;
  asio::post(s.server.get_io_service(), [&s, payload = std::move(text)] {
    s.send_all(payload, websocketpp::frame::opcode::text);
  });
}

void WebServer::broadcast_state(std::string text) {
  Impl& s = *impl_;
  asio::post(s.server.get_io_service(), [&s, payload = std::move(text)] {
    s.send_all(payload, websocketpp::frame::opcode::text, false);
  });
}

void WebServer::broadcast_binary(std::string bytes) {
  Impl& s = *impl_;
  asio::post(s.server.get_io_service(), [&s, payload = std::move(bytes)] {
    s.send_all(payload, websocketpp::frame::opcode::binary);
  });
}

std::size_t WebServer::frames_skipped() const { return impl_->skipped; }

}  // namespace macsim::web
