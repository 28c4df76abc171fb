// Samples of any IDL type between their wire form (XCDR1 with its encapsulation header) and
// YAML: printed as `ros2 topic echo` prints them, and filled from a YAML mapping for publishing.
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "wire_type.h"

namespace macsim::topic {

/// A sample or a YAML value that does not fit its type; the message names the field.
struct SampleError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// How a sample is printed.
struct YamlStyle {
  bool no_arrays = false;  ///< sequences and arrays as "<sequence type: T, length: N>"
  std::string field;       ///< print only this member: "pose.pose.position", "ranges.3"
};

/// The sample (encapsulation header + CDR) as YAML lines in the style of `ros2 topic echo`,
/// without the "---" separator. Throws SampleError for a sample that does not decode or a
/// field that does not exist (naming the members there are).
std::string sample_to_yaml(const std::vector<std::uint8_t>& sample, const WireType& type,
                           const YamlStyle& style = {});

/// A sample of `type` (little-endian XCDR1 with its header) holding what the YAML mapping
/// gives; members it does not name are zero or empty. Throws SampleError naming the field.
std::vector<std::uint8_t> sample_from_yaml(const YAML::Node& value, const WireType& type);

/// The instance key of a sample of a keyed struct, as Fast DDS computes it: the key members in
/// big-endian CDR, zero-padded to 16 bytes, or their MD5 when they may need more than 16.
/// Throws SampleError for a sample that does not decode or a key kind not supported.
std::array<std::uint8_t, 16> sample_key(const std::vector<std::uint8_t>& sample,
                                        const WireType& type);

}  // namespace macsim::topic
