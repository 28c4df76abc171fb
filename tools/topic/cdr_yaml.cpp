#include "cdr_yaml.h"

#include <fastrtps/utils/md5.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "macsim/dds/dynamic_types.h"

namespace macsim::topic {

using Kind = WireType::Kind;

namespace {

// ---- reading XCDR1 ----------------------------------------------------------------------------

/// A cursor over a serialized sample; alignment counts from the end of the 4-byte header.
class CdrIn {
 public:
  explicit CdrIn(const std::vector<std::uint8_t>& bytes) : bytes_(bytes) {
    if (bytes.size() < 4) throw SampleError("a sample shorter than its 4-byte header");
    if (bytes[0] != 0 || bytes[1] > 1) {
      throw SampleError("not a plain CDR sample (encapsulation " + std::to_string(bytes[0]) + "," +
                        std::to_string(bytes[1]) + ")");
    }
    little_ = bytes[1] == 1;
  }
  template <class T>
  T get() {
    align(sizeof(T));
    need(sizeof(T));
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, bytes_.data() + pos_, sizeof(T));
    if (!little_) std::reverse(raw, raw + sizeof(T));
    pos_ += sizeof(T);
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }
  std::string string() {
    const auto size = get<std::uint32_t>();
    need(size);
    if (size == 0) return {};
    std::string text(reinterpret_cast<const char*>(bytes_.data() + pos_), size - 1);
    pos_ += size;
    return text;
  }
  void skip_primitives(std::size_t size, std::uint64_t count) {
    if (count == 0) return;
    align(size);
    if (count > (bytes_.size() - pos_) / size) {
      throw SampleError("a sample that ends inside a sequence of " + std::to_string(count));
    }
    pos_ += size * count;
  }

 private:
  void align(std::size_t size) {
    const std::size_t offset = pos_ - 4;
    pos_ += (size - offset % size) % size;
  }
  void need(std::size_t size) const {
    if (pos_ > bytes_.size() || bytes_.size() - pos_ < size) {
      throw SampleError("the sample ends early (byte " + std::to_string(pos_) + " of " +
                        std::to_string(bytes_.size()) + ")");
    }
  }
  const std::vector<std::uint8_t>& bytes_;
  std::size_t pos_ = 4;
  bool little_ = true;
};

/// A number in the shortest text that reads back the same, as Python prints floats.
std::string float_text(double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
  char buffer[64];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string text(buffer, end);
  if (text.find_first_of(".en") == std::string::npos) text += ".0";
  return text;
}
std::string float_text(float value) {
  if (std::isnan(value) || std::isinf(value)) return float_text(static_cast<double>(value));
  char buffer[64];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string text(buffer, end);
  if (text.find_first_of(".en") == std::string::npos) text += ".0";
  return text;
}

/// A string as a YAML scalar: quoted where a plain scalar would read as something else.
std::string string_text(const std::string& text) {
  bool quote = text.empty() || text.front() == ' ' || text.back() == ' ';
  static const std::string special_first = "-?:,[]{}#&*!|>'\"%@`";
  if (!quote && special_first.find(text.front()) != std::string::npos) quote = true;
  if (!quote && (text.find(": ") != std::string::npos || text.find(" #") != std::string::npos ||
                 text.back() == ':' || text.find('\n') != std::string::npos)) {
    quote = true;
  }
  if (!quote) {
    static const char* words[] = {"true", "false", "yes", "no", "on", "off", "null", "~",
                                  "True", "False", "Yes", "No", "On", "Off", "Null", "NULL",
                                  "TRUE", "FALSE", "YES", "NO", "ON", "OFF"};
    for (const char* w : words) quote = quote || text == w;
    char* end = nullptr;
    std::strtod(text.c_str(), &end);
    if (end != text.c_str() && *end == '\0') quote = true;  // reads as a number
  }
  if (!quote) return text;
  std::string out = "'";
  for (char c : text) {
    if (c == '\'')
      out += "''";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out + "'";
}

std::string scalar_text(const WireType& type, CdrIn& in) {
  switch (type.kind) {
    case Kind::Bool:
      return in.get<std::uint8_t>() ? "true" : "false";
    case Kind::Octet:
      return std::to_string(in.get<std::uint8_t>());
    case Kind::Char:
      return std::to_string(in.get<std::int8_t>());
    case Kind::Int16:
      return std::to_string(in.get<std::int16_t>());
    case Kind::UInt16:
      return std::to_string(in.get<std::uint16_t>());
    case Kind::Int32:
      return std::to_string(in.get<std::int32_t>());
    case Kind::UInt32:
      return std::to_string(in.get<std::uint32_t>());
    case Kind::Int64:
      return std::to_string(in.get<std::int64_t>());
    case Kind::UInt64:
      return std::to_string(in.get<std::uint64_t>());
    case Kind::Float32:
      return float_text(in.get<float>());
    case Kind::Float64:
      return float_text(in.get<double>());
    case Kind::String:
      return string_text(in.string());
    case Kind::Enum: {
      const auto value = in.get<std::uint32_t>();
      return value < type.enumerators.size() ? type.enumerators[value] : std::to_string(value);
    }
    default:
      throw SampleError("not a scalar: " + display_name(type));
  }
}

std::int64_t discriminator(const WireType& type, CdrIn& in) {
  switch (type.kind) {
    case Kind::Bool:
    case Kind::Octet:
      return in.get<std::uint8_t>();
    case Kind::Char:
      return in.get<std::int8_t>();
    case Kind::Int16:
      return in.get<std::int16_t>();
    case Kind::UInt16:
      return in.get<std::uint16_t>();
    case Kind::Int32:
      return in.get<std::int32_t>();
    case Kind::UInt32:
    case Kind::Enum:
      return in.get<std::uint32_t>();
    case Kind::Int64:
      return in.get<std::int64_t>();
    case Kind::UInt64:
      return static_cast<std::int64_t>(in.get<std::uint64_t>());
    default:
      throw SampleError("a union discriminator of type " + display_name(type));
  }
}

const WireMember* union_case(const WireType& type, std::int64_t label) {
  const WireMember* fallback = nullptr;
  for (const auto& member : type.members) {
    for (auto l : member.labels) {
      if (l == label) return &member;
    }
    if (member.is_default) fallback = &member;
  }
  return fallback;
}

bool is_scalar(const WireType& type) {
  return is_primitive(type.kind) || type.kind == Kind::String;
}

std::uint64_t element_count(const WireType& type, CdrIn& in) {
  return type.kind == Kind::Array ? type.length : in.get<std::uint32_t>();
}

/// Reads one value; writes it as YAML lines at `indent` into `out`, or skips it if out is null.
/// Scalars go on the current line (the caller wrote "key: "); complex values begin with a
/// newline.
void print_value(const WireType& type, CdrIn& in, std::string* out, int indent,
                 const YamlStyle& style);

void print_members(const WireType& type, CdrIn& in, std::string* out, int indent,
                   const YamlStyle& style) {
  if (type.kind == Kind::Union) {
    const std::int64_t label = discriminator(*type.element, in);
    const WireMember* member = union_case(type, label);
    if (!member) {
      if (out) *out += std::string(indent, ' ') + "{}\n";
      return;
    }
    if (out) *out += std::string(indent, ' ') + member->name + ":";
    print_value(*member->type, in, out, indent + 2, style);
    return;
  }
  if (type.members.empty() && out) *out += std::string(indent, ' ') + "{}\n";
  for (const auto& member : type.members) {
    if (out) *out += std::string(indent, ' ') + member.name + ":";
    print_value(*member.type, in, out, indent + 2, style);
  }
}

void print_value(const WireType& type, CdrIn& in, std::string* out, int indent,
                 const YamlStyle& style) {
  if (is_scalar(type)) {
    std::string text = scalar_text(type, in);
    if (out) *out += " " + text + "\n";
    return;
  }
  if (type.kind == Kind::Struct || type.kind == Kind::Union) {
    if (out) *out += "\n";
    print_members(type, in, out, indent, style);
    return;
  }
  // a sequence or an array: items at the key's indent (PyYAML's block style)
  const std::uint64_t count = element_count(type, in);
  const WireType& element = *type.element;
  if (style.no_arrays || !out) {
    if (is_primitive(element.kind)) {
      in.skip_primitives(primitive_size(element.kind), count);
    } else {
      for (std::uint64_t i = 0; i < count; ++i) print_value(element, in, nullptr, 0, style);
    }
    if (out) {
      *out += type.kind == Kind::Array ? " '<array type: " + display_name(type) + ">'\n"
                                       : " '<sequence type: " + display_name(element) +
                                             ", length: " + std::to_string(count) + ">'\n";
    }
    return;
  }
  if (count == 0) {
    *out += " []\n";
    return;
  }
  *out += "\n";
  const int item_indent = indent - 2;
  for (std::uint64_t i = 0; i < count; ++i) {
    if (is_scalar(element)) {
      *out += std::string(item_indent, ' ') + "-";
      print_value(element, in, out, item_indent + 2, style);
    } else {
      std::string item;
      if (element.kind == Kind::Struct || element.kind == Kind::Union) {
        print_members(element, in, &item, item_indent + 2, style);
      } else {
        item = std::string(item_indent + 2, ' ') + "-";
        print_value(element, in, &item, item_indent + 4, style);
      }
      item.replace(0, static_cast<std::size_t>(item_indent) + 2,
                   std::string(item_indent, ' ') + "- ");
      *out += item;
    }
  }
}

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= path.size()) {
    const auto dot = path.find('.', start);
    parts.push_back(path.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

std::string member_list(const WireType& type) {
  std::string names;
  for (const auto& m : type.members) names += (names.empty() ? "" : ", ") + m.name;
  return names;
}

/// Prints the top-level value of a --field selection: no key, block style at indent 0.
std::string print_selected(const WireType& type, CdrIn& in, const YamlStyle& style) {
  std::string out;
  if (is_scalar(type)) {
    print_value(type, in, &out, 0, style);
    return out.substr(1);
  }
  if (type.kind == Kind::Struct || type.kind == Kind::Union) {
    print_members(type, in, &out, 0, style);
    return out;
  }
  print_value(type, in, &out, 2, style);
  return out.substr(1);
}

// ---- writing XCDR1 ----------------------------------------------------------------------------

class CdrOut {
 public:
  CdrOut() : bytes_{0, 1, 0, 0} {}  // CDR_LE
  template <class T>
  void put(T value) {
    align(sizeof(T));
    const auto* raw = reinterpret_cast<const std::uint8_t*>(&value);
    bytes_.insert(bytes_.end(), raw, raw + sizeof(T));
  }
  void string(const std::string& text) {
    put<std::uint32_t>(static_cast<std::uint32_t>(text.size() + 1));
    bytes_.insert(bytes_.end(), text.begin(), text.end());
    bytes_.push_back(0);
  }
  std::vector<std::uint8_t> take() { return std::move(bytes_); }

 private:
  void align(std::size_t size) {
    const std::size_t offset = bytes_.size() - 4;
    bytes_.resize(bytes_.size() + (size - offset % size) % size, 0);
  }
  std::vector<std::uint8_t> bytes_;
};

[[noreturn]] void bad_value(const std::string& field, const std::string& expected,
                            const YAML::Node& node) {
  std::string got = node.IsScalar()     ? "'" + node.Scalar() + "'"
                    : node.IsSequence() ? "a sequence"
                    : node.IsMap()      ? "a mapping"
                                        : "nothing";
  throw SampleError("field '" + field + "': expected " + expected + ", got " + got);
}

template <class Int>
Int integer(const YAML::Node& node, const std::string& field, const WireType& type) {
  if (!node.IsScalar()) bad_value(field, display_name(type), node);
  const std::string& text = node.Scalar();
  Int value{};
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) {
    bad_value(field, "an integer that fits " + display_name(type), node);
  }
  return value;
}

double floating(const YAML::Node& node, const std::string& field, const WireType& type) {
  if (!node.IsScalar()) bad_value(field, display_name(type), node);
  double value = 0;
  if (!YAML::convert<double>::decode(node, value)) bad_value(field, "a number", node);
  if (type.kind == Kind::Float32 && std::isfinite(value) &&
      std::abs(value) > std::numeric_limits<float>::max()) {
    bad_value(field, "a number that fits float32", node);
  }
  return value;
}

void write_default(const WireType& type, CdrOut& out, bool quaternion_w);

void write_value(const WireType& type, const YAML::Node& node, CdrOut& out,
                 const std::string& field);

void write_scalar(const WireType& type, const YAML::Node& node, CdrOut& out,
                  const std::string& field) {
  switch (type.kind) {
    case Kind::Bool: {
      bool value = false;
      if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value)) {
        bad_value(field, "true or false", node);
      }
      out.put<std::uint8_t>(value ? 1 : 0);
      return;
    }
    case Kind::Octet:
      out.put(integer<std::uint8_t>(node, field, type));
      return;
    case Kind::Char: {
      if (node.IsScalar() && node.Scalar().size() == 1 && !std::isdigit(node.Scalar()[0])) {
        out.put<std::int8_t>(static_cast<std::int8_t>(node.Scalar()[0]));
      } else {
        out.put(integer<std::int8_t>(node, field, type));
      }
      return;
    }
    case Kind::Int16:
      out.put(integer<std::int16_t>(node, field, type));
      return;
    case Kind::UInt16:
      out.put(integer<std::uint16_t>(node, field, type));
      return;
    case Kind::Int32:
      out.put(integer<std::int32_t>(node, field, type));
      return;
    case Kind::UInt32:
      out.put(integer<std::uint32_t>(node, field, type));
      return;
    case Kind::Int64:
      out.put(integer<std::int64_t>(node, field, type));
      return;
    case Kind::UInt64:
      out.put(integer<std::uint64_t>(node, field, type));
      return;
    case Kind::Float32:
      out.put(static_cast<float>(floating(node, field, type)));
      return;
    case Kind::Float64:
      out.put(floating(node, field, type));
      return;
    case Kind::String: {
      if (!node.IsScalar()) bad_value(field, "a string", node);
      if (type.length != 0 && node.Scalar().size() > type.length) {
        bad_value(field, "a string of at most " + std::to_string(type.length) + " characters",
                  node);
      }
      out.string(node.Scalar());
      return;
    }
    case Kind::Enum: {
      if (!node.IsScalar()) bad_value(field, "an enumerator", node);
      for (std::size_t i = 0; i < type.enumerators.size(); ++i) {
        if (type.enumerators[i] == node.Scalar()) {
          out.put(static_cast<std::uint32_t>(i));
          return;
        }
      }
      out.put(integer<std::uint32_t>(node, field, type));
      return;
    }
    default:
      throw SampleError("field '" + field + "' is not a scalar");
  }
}

void write_discriminator(const WireType& type, std::int64_t label, CdrOut& out) {
  switch (primitive_size(type.kind)) {
    case 1:
      out.put(static_cast<std::uint8_t>(label));
      break;
    case 2:
      out.put(static_cast<std::uint16_t>(label));
      break;
    case 4:
      out.put(static_cast<std::uint32_t>(label));
      break;
    default:
      out.put(static_cast<std::uint64_t>(label));
      break;
  }
}

std::int64_t label_of(const WireType& type, const WireMember& member) {
  if (!member.labels.empty()) return member.labels.front();
  // the default case: a label no member names
  std::int64_t label = 0;
  while (union_case(type, label) != &member) ++label;
  return label;
}

std::string join(const std::string& field, const std::string& name) {
  return field.empty() ? name : field + "." + name;
}

void write_value(const WireType& type, const YAML::Node& node, CdrOut& out,
                 const std::string& field) {
  if (is_scalar(type)) {
    write_scalar(type, node, out, field);
    return;
  }
  if (type.kind == Kind::Struct) {
    if (!node.IsMap() && !node.IsNull()) {
      bad_value(field.empty() ? display_name(type) : field,
                "a mapping of " + display_name(type) + " (fields: " + member_list(type) + ")",
                node);
    }
    if (node.IsMap()) {
      for (const auto& entry : node) {
        const std::string key = entry.first.as<std::string>();
        bool known = false;
        for (const auto& m : type.members) known = known || m.name == key;
        if (!known) {
          throw SampleError("no field '" + join(field, key) + "' in " + display_name(type) +
                            " (fields: " + member_list(type) + ")");
        }
      }
    }
    const bool quaternion = type.name == "geometry_msgs::msg::dds_::Quaternion_";
    for (const auto& m : type.members) {
      const YAML::Node given = node.IsMap() ? node[m.name] : YAML::Node();
      if (given.IsDefined() && !given.IsNull()) {
        write_value(*m.type, given, out, join(field, m.name));
      } else {
        write_default(*m.type, out, quaternion && m.name == "w");
      }
    }
    return;
  }
  if (type.kind == Kind::Union) {
    if (!node.IsMap() || node.size() != 1) {
      bad_value(field.empty() ? display_name(type) : field,
                "a mapping with one of " + member_list(type), node);
    }
    const std::string key = node.begin()->first.as<std::string>();
    for (const auto& m : type.members) {
      if (m.name != key) continue;
      write_discriminator(*type.element, label_of(type, m), out);
      write_value(*m.type, node.begin()->second, out, join(field, key));
      return;
    }
    throw SampleError("no case '" + join(field, key) + "' in " + display_name(type) +
                      " (cases: " + member_list(type) + ")");
  }
  // sequence or array
  if (!node.IsSequence() && !node.IsNull()) bad_value(field, "a sequence", node);
  const std::size_t count = node.IsSequence() ? node.size() : 0;
  if (type.kind == Kind::Array) {
    if (count != type.length) {
      bad_value(field, "a sequence of exactly " + std::to_string(type.length) + " items", node);
    }
  } else {
    if (type.length != 0 && count > type.length) {
      bad_value(field, "at most " + std::to_string(type.length) + " items", node);
    }
    out.put(static_cast<std::uint32_t>(count));
  }
  for (std::size_t i = 0; i < count; ++i) {
    write_value(*type.element, node[i], out, join(field, std::to_string(i)));
  }
}

void write_default(const WireType& type, CdrOut& out, bool quaternion_w) {
  if (quaternion_w) {  // ROS's Quaternion.msg declares w = 1: the identity
    out.put(1.0);
    return;
  }
  switch (type.kind) {
    case Kind::String:
      out.string("");
      return;
    case Kind::Sequence:
      out.put<std::uint32_t>(0);
      return;
    case Kind::Array:
      for (std::uint32_t i = 0; i < type.length; ++i) write_default(*type.element, out, false);
      return;
    case Kind::Struct: {
      const bool quaternion = type.name == "geometry_msgs::msg::dds_::Quaternion_";
      for (const auto& m : type.members) write_default(*m.type, out, quaternion && m.name == "w");
      return;
    }
    case Kind::Union:
      if (type.members.empty()) {
        write_discriminator(*type.element, 0, out);
        return;
      }
      write_discriminator(*type.element, label_of(type, type.members.front()), out);
      write_default(*type.members.front().type, out, false);
      return;
    default:
      switch (primitive_size(type.kind)) {
        case 1:
          out.put<std::uint8_t>(0);
          return;
        case 2:
          out.put<std::uint16_t>(0);
          return;
        case 4:
          out.put<std::uint32_t>(0);
          return;
        default:
          out.put<std::uint64_t>(0);
          return;
      }
  }
}

}  // namespace

std::string sample_to_yaml(const std::vector<std::uint8_t>& sample, const WireType& type,
                           const YamlStyle& style) {
  CdrIn in(sample);
  if (style.field.empty()) {
    std::string out;
    print_members(type, in, &out, 0, style);
    return out;
  }
  // walk down the path, skipping what lies before each step
  const WireType* at = &type;
  std::string walked;
  for (const std::string& step : split_path(style.field)) {
    walked = join(walked, step);
    if (at->kind == Kind::Struct) {
      const WireMember* found = nullptr;
      for (const auto& m : at->members) {
        if (m.name == step) {
          found = &m;
          break;
        }
        print_value(*m.type, in, nullptr, 0, style);
      }
      if (!found) {
        throw SampleError("no field '" + walked + "' in " + display_name(*at) +
                          " (fields: " + member_list(*at) + ")");
      }
      at = found->type.get();
    } else if (at->kind == Kind::Union) {
      const WireMember* active = union_case(*at, discriminator(*at->element, in));
      if (!active || active->name != step) {
        throw SampleError("field '" + walked + "' is not the case this sample holds" +
                          (active ? " (it holds '" + active->name + "')" : std::string()));
      }
      at = active->type.get();
    } else if (at->kind == Kind::Sequence || at->kind == Kind::Array) {
      std::uint64_t index = 0;
      auto [end, ec] = std::from_chars(step.data(), step.data() + step.size(), index);
      if (ec != std::errc() || end != step.data() + step.size()) {
        throw SampleError("field '" + walked + "': a sequence takes an index, not '" + step + "'");
      }
      const std::uint64_t count = element_count(*at, in);
      if (index >= count) {
        throw SampleError("field '" + walked + "': index out of range (length " +
                          std::to_string(count) + ")");
      }
      for (std::uint64_t i = 0; i < index; ++i) print_value(*at->element, in, nullptr, 0, style);
      at = at->element.get();
    } else {
      throw SampleError("field '" + walked + "': " + display_name(*at) + " has no members");
    }
  }
  return print_selected(*at, in, style);
}

std::array<std::uint8_t, 16> sample_key(const std::vector<std::uint8_t>& sample,
                                        const WireType& type) {
  CdrIn in(sample);
  std::vector<std::uint8_t> key;  // big-endian CDR of the key members, aligned from 0
  bool bounded = true;            // fits 16 bytes whatever the values (no string)
  auto put = [&key](const std::uint8_t* raw, std::size_t size) {
    key.resize(key.size() + (size - key.size() % size) % size, 0);
    for (std::size_t i = size; i-- > 0;) key.push_back(raw[i]);  // little -> big endian
  };
  for (const auto& m : type.members) {
    if (!m.key) {
      print_value(*m.type, in, nullptr, 0, {});
      continue;
    }
    switch (m.type->kind) {
      case Kind::String: {
        const std::string text = in.string();
        const auto size = static_cast<std::uint32_t>(text.size() + 1);
        put(reinterpret_cast<const std::uint8_t*>(&size), 4);
        key.insert(key.end(), text.begin(), text.end());
        key.push_back(0);
        bounded = false;
        break;
      }
      case Kind::Bool:
      case Kind::Octet:
      case Kind::Char: {
        const auto v = in.get<std::uint8_t>();
        put(&v, 1);
        break;
      }
      case Kind::Int16:
      case Kind::UInt16: {
        const auto v = in.get<std::uint16_t>();
        put(reinterpret_cast<const std::uint8_t*>(&v), 2);
        break;
      }
      case Kind::Int32:
      case Kind::UInt32:
      case Kind::Float32:
      case Kind::Enum: {
        const auto v = in.get<std::uint32_t>();
        put(reinterpret_cast<const std::uint8_t*>(&v), 4);
        break;
      }
      case Kind::Int64:
      case Kind::UInt64:
      case Kind::Float64: {
        const auto v = in.get<std::uint64_t>();
        put(reinterpret_cast<const std::uint8_t*>(&v), 8);
        break;
      }
      default:
        throw SampleError(display_name(type) + ": a key member of type " + display_name(*m.type) +
                          " is not supported");
    }
  }
  std::array<std::uint8_t, 16> out{};
  if (bounded && key.size() <= 16) {
    std::copy(key.begin(), key.end(), out.begin());
  } else {
    MD5 md5;
    md5.init();
    md5.update(key.data(), static_cast<unsigned int>(key.size()));
    md5.finalize();
    std::copy(md5.digest, md5.digest + 16, out.begin());
  }
  return out;
}

std::vector<std::uint8_t> sample_from_yaml(const YAML::Node& value, const WireType& type) {
  CdrOut out;
  write_value(type, value, out, "");
  return out.take();
}

}  // namespace macsim::topic
