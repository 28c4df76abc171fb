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
      out->length = descriptor->get_bounds();
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

}  // namespace macsim::topic
