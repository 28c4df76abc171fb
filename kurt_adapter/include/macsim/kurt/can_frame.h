// One classic CAN frame and the transports that carry them (SocketCAN, or UDP for tests).
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace macsim::kurt {

/// A classic CAN frame: 11-bit id, up to 8 data bytes.
struct CanFrame {
  uint32_t id = 0;
  uint8_t dlc = 8;
  std::array<uint8_t, 8> data{};
  bool operator==(const CanFrame& other) const = default;
};

/// A frame as one datagram of the userspace bus: 16 bytes, SocketCAN's frame layout with the
/// id in network order.
std::array<uint8_t, 16> to_datagram(const CanFrame& frame);
/// The frame of a datagram; nothing unless it is 16 bytes with a length code of at most 8.
std::optional<CanFrame> from_datagram(const uint8_t* bytes, std::size_t size);

/// Raised when a CAN transport cannot be opened or used; the message says which and why.
struct CanError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Sends and receives CAN frames. One reader thread and any number of senders.
class CanTransport {
 public:
  virtual ~CanTransport() = default;
  /// Sends one frame; false if the bus refused it.
  virtual bool send(const CanFrame& frame) = 0;
  /// The next frame, or nothing if none came within `timeout`.
  virtual std::optional<CanFrame> receive(std::chrono::milliseconds timeout) = 0;
};

/// SocketCAN on a Linux CAN interface (the real robot: `can0`). Throws CanError if the
/// kernel has no CAN support or the interface does not exist.
std::unique_ptr<CanTransport> open_socketcan(const std::string& interface);

/// The userspace bus: CAN frames as 16-byte UDP datagrams (SocketCAN's frame layout, id and
/// dlc in network order) between two ports of 127.0.0.1, for tests and the emulator.
std::unique_ptr<CanTransport> open_udp_bus(int local_port, int peer_port);

/// Opens "socketcan:IFACE" or "udp:LOCAL_PORT:PEER_PORT"; throws CanError naming the problem.
std::unique_ptr<CanTransport> open_can(const std::string& spec);

}  // namespace macsim::kurt
