// A sample in its wire form (CDR, with its encapsulation) and back, as a writer sends it and a
// reader takes it: for commands kept as values (a recorded session) and for fuzzing.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "macsim/dds/participant.h"

namespace macsim::dds {

/// The digest of the wire types a session's recorded bytes are made of (16 hex digits, from the
/// IDL files at build time: a type, field or annotation changed changes it, a comment does not).
std::string_view session_wire_types();

/// The sample's bytes as a DataWriter of its type would send them.
template <class PubSubType>
std::vector<uint8_t> to_wire(const typename PubSubType::type& sample) {
  PubSubType type;
  auto* data = const_cast<typename PubSubType::type*>(&sample);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(data)());
  if (!type.serialize(data, &payload)) return {};
  return std::vector<uint8_t>(payload.data, payload.data + payload.length);
}

/// The sample those bytes hold, or nullopt when they are not one (as a reader drops it).
template <class PubSubType>
std::optional<typename PubSubType::type> from_wire(const uint8_t* bytes, std::size_t size) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<uint32_t>(size));
  std::copy(bytes, bytes + size, payload.data);
  payload.length = static_cast<uint32_t>(size);
  CheckedType<PubSubType> type;
  typename PubSubType::type sample;
  if (!type.deserialize(&payload, &sample)) return std::nullopt;
  return sample;
}

template <class PubSubType>
std::optional<typename PubSubType::type> from_wire(const std::vector<uint8_t>& bytes) {
  return from_wire<PubSubType>(bytes.data(), bytes.size());
}

}  // namespace macsim::dds
