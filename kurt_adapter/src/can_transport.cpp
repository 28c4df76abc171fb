#include <arpa/inet.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "macsim/kurt/can_frame.h"

namespace macsim::kurt {

std::array<uint8_t, 16> to_datagram(const CanFrame& frame) {
  std::array<uint8_t, 16> bytes{};
  const uint32_t id = htonl(frame.id);
  std::memcpy(bytes.data(), &id, 4);
  bytes[4] = frame.dlc;
  std::memcpy(bytes.data() + 8, frame.data.data(), 8);
  return bytes;
}

std::optional<CanFrame> from_datagram(const uint8_t* bytes, std::size_t size) {
  if (size != 16 || bytes[4] > 8) return std::nullopt;
  CanFrame frame;
  uint32_t id;
  std::memcpy(&id, bytes, 4);
  frame.id = ntohl(id);
  frame.dlc = bytes[4];
  std::memcpy(frame.data.data(), bytes + 8, 8);
  return frame;
}
namespace {

/// Waits until `fd` is readable; false on timeout.
bool readable(int fd, std::chrono::milliseconds timeout) {
  pollfd p{fd, POLLIN, 0};
  int r;
  do {
    r = ::poll(&p, 1, static_cast<int>(timeout.count()));
  } while (r < 0 && errno == EINTR);
  return r > 0 && (p.revents & POLLIN);
}

/// Time left until `deadline`, never negative.
std::chrono::milliseconds remaining(std::chrono::steady_clock::time_point deadline) {
  return std::max(std::chrono::milliseconds(0),
                  std::chrono::duration_cast<std::chrono::milliseconds>(
                      deadline - std::chrono::steady_clock::now()));
}

class SocketCan final : public CanTransport {
 public:
  explicit SocketCan(const std::string& interface) {
    fd_ = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd_ < 0) {
      const int error = errno;
      throw CanError(error == EAFNOSUPPORT || error == EPROTONOSUPPORT
                         ? "SocketCAN: this kernel has no CAN support (socket(PF_CAN): " +
                               std::string(std::strerror(error)) +
                               "); use the userspace bus (--can udp:LOCAL:PEER) without hardware"
                         : "SocketCAN: socket(PF_CAN): " + std::string(std::strerror(error)));
    }
    const unsigned index = if_nametoindex(interface.c_str());
    if (index == 0) {
      ::close(fd_);
      throw CanError("SocketCAN: no CAN interface '" + interface + "' (is it up? ip link)");
    }
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(index);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) < 0) {
      const int error = errno;
      ::close(fd_);
      throw CanError("SocketCAN: bind to '" + interface + "': " + std::strerror(error));
    }
  }
  ~SocketCan() override { ::close(fd_); }

  bool send(const CanFrame& frame) override {
    can_frame raw{};
    raw.can_id = frame.id;
    raw.can_dlc = frame.dlc;
    std::memcpy(raw.data, frame.data.data(), 8);
    return ::write(fd_, &raw, sizeof raw) == static_cast<ssize_t>(sizeof raw);
  }
  std::optional<CanFrame> receive(std::chrono::milliseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    can_frame raw{};
    while (true) {  // until a frame of the KURT's kind comes, or the time is up
      if (!readable(fd_, remaining(deadline))) return std::nullopt;
      if (::read(fd_, &raw, sizeof raw) != static_cast<ssize_t>(sizeof raw)) continue;
      // The KURT speaks 11-bit data frames only: an extended, remote or error frame is not one
      // of its frames (masking its id would read it as one).
      if (!(raw.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG))) break;
    }
    CanFrame frame;
    frame.id = raw.can_id & CAN_SFF_MASK;
    frame.dlc = raw.can_dlc;
    std::memcpy(frame.data.data(), raw.data, 8);
    return frame;
  }

 private:
  int fd_ = -1;
};

class UdpBus final : public CanTransport {
 public:
  UdpBus(int local_port, int peer_port) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (fd_ < 0) throw CanError(std::string("udp bus: socket: ") + std::strerror(errno));
    sockaddr_in local = loopback(local_port);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) < 0) {
      const int error = errno;
      ::close(fd_);
      throw CanError("udp bus: cannot bind 127.0.0.1:" + std::to_string(local_port) + ": " +
                     std::strerror(error));
    }
    peer_ = loopback(peer_port);
  }
  ~UdpBus() override { ::close(fd_); }

  bool send(const CanFrame& frame) override {
    const auto bytes = to_datagram(frame);
    return ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&peer_),
                    sizeof peer_) == static_cast<ssize_t>(bytes.size());
  }
  std::optional<CanFrame> receive(std::chrono::milliseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    uint8_t bytes[17];  // one more: a longer datagram is seen as such
    while (true) {      // a datagram that is not a frame is skipped
      if (!readable(fd_, remaining(deadline))) return std::nullopt;
      const ssize_t n = ::recv(fd_, bytes, sizeof bytes, 0);
      if (n < 0) continue;
      if (auto frame = from_datagram(bytes, std::size_t(n))) return frame;
    }
  }

 private:
  static sockaddr_in loopback(int port) {
    if (port <= 0 || port > 65535) throw CanError("udp bus: bad port " + std::to_string(port));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return a;
  }
  int fd_ = -1;
  sockaddr_in peer_{};
};

}  // namespace

std::unique_ptr<CanTransport> open_socketcan(const std::string& interface) {
  return std::make_unique<SocketCan>(interface);
}

std::unique_ptr<CanTransport> open_udp_bus(int local_port, int peer_port) {
  return std::make_unique<UdpBus>(local_port, peer_port);
}

std::unique_ptr<CanTransport> open_can(const std::string& spec) {
  if (spec.rfind("socketcan:", 0) == 0) return open_socketcan(spec.substr(10));
  int local = 0, peer = 0;
  char end = 0;
  if (std::sscanf(spec.c_str(), "udp:%d:%d%c", &local, &peer, &end) == 2) {
    return open_udp_bus(local, peer);
  }
  throw CanError("bad CAN bus '" + spec + "': use socketcan:IFACE (e.g. socketcan:can0) or " +
                 "udp:LOCAL_PORT:PEER_PORT");
}

}  // namespace macsim::kurt
