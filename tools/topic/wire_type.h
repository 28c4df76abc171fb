// A compact description of one IDL type as it lies on the wire (XCDR1), built once from the
// IDL's dynamic type: what the CDR reader and writer of the topic tools walk.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace macsim::topic {

struct WireType;
using WireTypePtr = std::shared_ptr<const WireType>;

/// A member of a struct or union.
struct WireMember {
  std::string name;
  WireTypePtr type;
  std::vector<std::int64_t> labels;  ///< union cases that select this member
  bool is_default = false;           ///< union: the default case
  bool key = false;                  ///< struct: a key member (@key)
};

/// One type: a primitive, a string, a struct, a union, a sequence or an array.
struct WireType {
  enum class Kind {
    Bool,
    Octet,
    Char,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Float32,
    Float64,
    String,
    Enum,
    Struct,
    Union,
    Sequence,
    Array
  };
  Kind kind = Kind::Octet;
  std::string name;                      ///< DDS type name of structs and unions, else the IDL name
  std::vector<WireMember> members;       ///< struct members in wire order; union cases
  std::vector<std::string> enumerators;  ///< enum: names by value
  WireTypePtr element;                   ///< sequence and array: the element; union: discriminator
  std::uint32_t length = 0;              ///< array: element count (all dimensions); sequence: bound
};

/// Whether a struct has key members (its topics have one instance per key).
bool is_keyed(const WireType& type);
/// The wire description of a DDS type name from the IDL, or null if the IDL has no such type.
WireTypePtr wire_type(const std::string& dds_type_name);
/// Size in bytes (and alignment) of a primitive kind; 0 for the others.
std::size_t primitive_size(WireType::Kind kind);
/// Whether a type is a primitive (a number, bool, octet, char or enum).
bool is_primitive(WireType::Kind kind);
/// The IDL-ish name of a type for messages: "float64", "string", "geometry_msgs/msg/Twist".
std::string display_name(const WireType& type);

/// The struct as a ROS 2 .msg definition: one "type name" line per member, in wire order
/// (nested types of its own package by their short name, others as "pkg/Type"). Empty for a
/// type .msg cannot express (a union in it).
std::string ros2_msg_definition(const WireType& type);
/// The same followed by every nested type's definition, as rosbag2 stores message definitions
/// ("ros2msg": each after a line of 80 '=' and "MSG: pkg/Type").
std::string ros2_msg_with_dependencies(const WireType& type);

}  // namespace macsim::topic
