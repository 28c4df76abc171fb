#include "wire_type.h"

#include <fastrtps/types/DynamicType.h>
#include <fastrtps/types/DynamicTypeMember.h>
#include <fastrtps/types/MemberDescriptor.h>
#include <fastrtps/types/TypeDescriptor.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <stdexcept>

#include "macsim/dds/dynamic_types.h"

namespace macsim::topic {

namespace types = eprosima::fastrtps::types;
using Kind = WireType::Kind;

namespace {

types::DynamicType_ptr resolve_alias(types::DynamicType_ptr type) {
  while (type && type->get_kind() == types::TK_ALIAS) {
    type = type->get_descriptor()->get_base_type();
  }
  return type;
}

WireTypePtr describe(types::DynamicType_ptr type, std::map<std::string, WireTypePtr>& done);

std::vector<WireMember> describe_members(const types::DynamicType_ptr& type,
                                         std::map<std::string, WireTypePtr>& done) {
  std::map<types::MemberId, types::DynamicTypeMember*> by_id;
  type->get_all_members(by_id);
  std::vector<std::pair<std::uint32_t, WireMember>> members;
  for (const auto& [id, member] : by_id) {
    const types::MemberDescriptor* descriptor = member->get_descriptor();
    WireMember out;
    out.name = descriptor->get_name();
    out.type = describe(descriptor->get_type(), done);
    for (std::uint64_t label : descriptor->get_union_labels()) {
      out.labels.push_back(static_cast<std::int64_t>(label));
    }
    out.is_default = descriptor->is_default_union_value();
    out.key = member->key_annotation();
    members.emplace_back(descriptor->get_index(), std::move(out));
  }
  std::stable_sort(members.begin(), members.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<WireMember> ordered;
  for (auto& m : members) ordered.push_back(std::move(m.second));
  return ordered;
}

/// The full DDS name of a type that the type objects name by its last part ("Pose_").
std::string full_name(const std::string& name) {
  if (name.find("::") != std::string::npos) return name;
  std::string found;
  for (const auto& full : dds::idl_type_names()) {
    if (full.size() > name.size() + 2 &&
        full.compare(full.size() - name.size(), name.size(), name) == 0 &&
        full.compare(full.size() - name.size() - 2, 2, "::") == 0) {
      if (!found.empty()) return name;  // ambiguous: keep the short name
      found = full;
    }
  }
  return found.empty() ? name : found;
}

WireTypePtr describe(types::DynamicType_ptr type, std::map<std::string, WireTypePtr>& done) {
  type = resolve_alias(type);
  if (!type) throw std::runtime_error("a member of an IDL type has no type");
  auto out = std::make_shared<WireType>();
  out->name = full_name(type->get_name());
  const types::TypeDescriptor* descriptor = type->get_descriptor();
  switch (type->get_kind()) {
    case types::TK_BOOLEAN:
      out->kind = Kind::Bool;
      break;
    case types::TK_BYTE:
      out->kind = Kind::Octet;
      break;
    case types::TK_CHAR8:
      out->kind = Kind::Char;
      break;
    case types::TK_INT16:
      out->kind = Kind::Int16;
      break;
    case types::TK_UINT16:
      out->kind = Kind::UInt16;
      break;
    case types::TK_INT32:
      out->kind = Kind::Int32;
      break;
    case types::TK_UINT32:
      out->kind = Kind::UInt32;
      break;
    case types::TK_INT64:
      out->kind = Kind::Int64;
      break;
    case types::TK_UINT64:
      out->kind = Kind::UInt64;
      break;
    case types::TK_FLOAT32:
      out->kind = Kind::Float32;
      break;
    case types::TK_FLOAT64:
      out->kind = Kind::Float64;
      break;
    case types::TK_STRING8:
      out->kind = Kind::String;
      // Fast DDS 2.9 gives an unbounded string the bound MAX_STRING_LENGTH; the IDL bounds none.
      out->length =
          descriptor->get_bounds() == types::MAX_STRING_LENGTH ? 0 : descriptor->get_bounds();
      break;
    case types::TK_ENUM: {
      out->kind = Kind::Enum;
      std::map<types::MemberId, types::DynamicTypeMember*> by_id;
      type->get_all_members(by_id);
      for (const auto& [id, member] : by_id) {
        if (out->enumerators.size() <= id) out->enumerators.resize(id + 1);
        out->enumerators[id] = member->get_name();
      }
      break;
    }
    case types::TK_STRUCTURE: {
      auto known = done.find(out->name);
      if (known != done.end()) return known->second;
      out->kind = Kind::Struct;
      if (descriptor->get_base_type()) {
        throw std::runtime_error(out->name + ": inheritance is not used on the wire here");
      }
      out->members = describe_members(type, done);
      break;
    }
    case types::TK_UNION: {
      auto known = done.find(out->name);
      if (known != done.end()) return known->second;
      out->kind = Kind::Union;
      out->element = describe(descriptor->get_discriminator_type(), done);
      out->members = describe_members(type, done);
      break;
    }
    case types::TK_SEQUENCE:
      out->kind = Kind::Sequence;
      out->element = describe(descriptor->get_element_type(), done);
      out->length = descriptor->get_bounds();
      break;
    case types::TK_ARRAY:
      out->kind = Kind::Array;
      out->element = describe(descriptor->get_element_type(), done);
      out->length = descriptor->get_total_bounds();
      break;
    default:
      throw std::runtime_error(out->name + ": a kind of type the IDL does not use (kind " +
                               std::to_string(static_cast<int>(type->get_kind())) + ")");
  }
  if (out->kind == Kind::Struct || out->kind == Kind::Union) done[out->name] = out;
  return out;
}

}  // namespace

WireTypePtr wire_type(const std::string& dds_type_name) {
  static std::mutex mutex;
  static std::map<std::string, WireTypePtr> done;
  std::lock_guard<std::mutex> lock(mutex);
  auto known = done.find(dds_type_name);
  if (known != done.end()) return known->second;
  types::DynamicType_ptr dynamic = dds::idl_dynamic_type(dds_type_name);
  if (!dynamic) return {};
  return describe(dynamic, done);
}

bool is_keyed(const WireType& type) {
  for (const auto& m : type.members) {
    if (m.key) return true;
  }
  return false;
}

std::size_t primitive_size(Kind kind) {
  switch (kind) {
    case Kind::Bool:
    case Kind::Octet:
    case Kind::Char:
      return 1;
    case Kind::Int16:
    case Kind::UInt16:
      return 2;
    case Kind::Int32:
    case Kind::UInt32:
    case Kind::Float32:
    case Kind::Enum:
      return 4;
    case Kind::Int64:
    case Kind::UInt64:
    case Kind::Float64:
      return 8;
    default:
      return 0;
  }
}

bool is_primitive(Kind kind) { return primitive_size(kind) != 0; }

std::string display_name(const WireType& type) {
  switch (type.kind) {
    case Kind::Bool:
      return "boolean";
    case Kind::Octet:
      return "uint8";
    case Kind::Char:
      return "char";
    case Kind::Int16:
      return "int16";
    case Kind::UInt16:
      return "uint16";
    case Kind::Int32:
      return "int32";
    case Kind::UInt32:
      return "uint32";
    case Kind::Int64:
      return "int64";
    case Kind::UInt64:
      return "uint64";
    case Kind::Float32:
      return "float32";
    case Kind::Float64:
      return "float64";
    case Kind::String:
      return "string";
    case Kind::Enum:
      return type.name;
    case Kind::Struct:
    case Kind::Union:
      return dds::ros_type_name(type.name);
    case Kind::Sequence:
      return "sequence<" + display_name(*type.element) + ">";
    case Kind::Array:
      return display_name(*type.element) + "[" + std::to_string(type.length) + "]";
  }
  return type.name;
}

namespace {

std::string package_of(const std::string& dds_name) {
  return dds_name.substr(0, dds_name.find("::"));
}

/// The .msg spelling of a member's type; empty if .msg has none (a union).
std::string msg_type(const WireType& t, const std::string& package) {
  switch (t.kind) {
    case Kind::Bool:
      return "bool";
    case Kind::Octet:
      return "uint8";
    case Kind::Char:
      return "int8";
    case Kind::Enum:
      return "uint32";
    case Kind::String:
      return t.length ? "string<=" + std::to_string(t.length) : "string";
    case Kind::Struct: {
      const std::string ros = dds::ros_type_name(t.name);  // pkg/msg/Name
      const std::string pkg = ros.substr(0, ros.find('/'));
      const std::string name = ros.substr(ros.rfind('/') + 1);
      return pkg == package ? name : pkg + "/" + name;
    }
    case Kind::Union:
      return "";
    case Kind::Sequence: {
      const std::string element = msg_type(*t.element, package);
      if (element.empty()) return "";
      return element + (t.length ? "[<=" + std::to_string(t.length) + "]" : "[]");
    }
    case Kind::Array: {
      const std::string element = msg_type(*t.element, package);
      return element.empty() ? "" : element + "[" + std::to_string(t.length) + "]";
    }
    default:
      return display_name(t);  // int16 ... float64: the same words
  }
}

void collect_nested(const WireType& type, std::vector<const WireType*>& out) {
  for (const auto& m : type.members) {
    const WireType* inner = m.type.get();
    while (inner->kind == Kind::Sequence || inner->kind == Kind::Array)
      inner = inner->element.get();
    if (inner->kind != Kind::Struct) continue;
    if (std::find(out.begin(), out.end(), inner) != out.end()) continue;
    out.push_back(inner);
    collect_nested(*inner, out);
  }
}

}  // namespace

std::string ros2_msg_definition(const WireType& type) {
  if (type.kind != Kind::Struct) return {};
  const std::string package = package_of(type.name);
  std::string out;
  for (const auto& m : type.members) {
    const std::string t = msg_type(*m.type, package);
    if (t.empty()) return {};
    out += t + " " + m.name + "\n";
  }
  return out;
}

std::string ros2_msg_with_dependencies(const WireType& type) {
  std::string out = ros2_msg_definition(type);
  if (out.empty()) return out;
  std::vector<const WireType*> nested;
  collect_nested(type, nested);
  for (const WireType* n : nested) {
    const std::string ros = dds::ros_type_name(n->name);  // pkg/msg/Name -> pkg/Name
    out += std::string(80, '=') + "\nMSG: " + ros.substr(0, ros.find('/')) +
           ros.substr(ros.rfind('/')) + "\n" + ros2_msg_definition(*n);
  }
  return out;
}

}  // namespace macsim::topic
