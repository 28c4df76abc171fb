#include "macsim/dds/dynamic_types.h"

#include <fastrtps/types/TypeObjectFactory.h>

#include <algorithm>
#include <mutex>

#include "dynamic_type_registry.inc"

namespace macsim::dds {

namespace types = eprosima::fastrtps::types;

namespace {

void register_idl_types() {
  static std::once_flag once;
  std::call_once(once, [] { register_idl_files(); });
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

}  // namespace

const std::vector<std::string>& idl_type_names() {
  static const std::vector<std::string> names = {
#include "dynamic_type_list.inc"
  };
  return names;
}

types::DynamicType_ptr idl_dynamic_type(const std::string& dds_name) {
  if (!std::binary_search(idl_type_names().begin(), idl_type_names().end(), dds_name)) {
    return {};
  }
  register_idl_types();
  static std::mutex mutex;  // the factory builds types one at a time
  std::lock_guard<std::mutex> lock(mutex);
  auto* factory = types::TypeObjectFactory::get_instance();
  const types::TypeIdentifier* id = factory->get_type_identifier(dds_name, true);
  const types::TypeObject* object = factory->get_type_object(dds_name, true);
  if (id == nullptr || object == nullptr) return {};
  return factory->build_dynamic_type(dds_name, id, object);
}

std::string ros_type_name(const std::string& dds_name) {
  // pkg::msg::dds_::Name_ -> pkg/msg/Name
  const auto dds = dds_name.find("::dds_::");
  if (dds == std::string::npos || dds_name.back() != '_') return dds_name;
  std::string prefix = dds_name.substr(0, dds);  // pkg::msg
  const auto sep = prefix.find("::");
  if (sep == std::string::npos) return dds_name;
  prefix.replace(sep, 2, "/");
  const std::string name = dds_name.substr(dds + 8, dds_name.size() - dds - 9);
  return prefix + "/" + name;
}

std::string dds_type_name(const std::string& name) {
  if (name.find("::") != std::string::npos) return name;
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const auto slash = name.find('/', start);
    parts.push_back(name.substr(start, slash - start));
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  if (parts.size() == 2) parts.insert(parts.begin() + 1, "msg");
  if (parts.size() != 3) return name;
  return parts[0] + "::" + parts[1] + "::dds_::" + parts[2] + "_";
}

std::string ros_topic_name(const std::string& dds_topic) {
  if (!starts_with(dds_topic, "rt/")) return {};
  return dds_topic.substr(2);
}

std::string dds_topic_name(const std::string& topic) {
  if (starts_with(topic, "rt/") || starts_with(topic, "rq/") || starts_with(topic, "rr/")) {
    return topic;
  }
  return "rt/" + (starts_with(topic, "/") ? topic.substr(1) : topic);
}

}  // namespace macsim::dds
