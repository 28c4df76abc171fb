#include "macsim/sim_core/world_loader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

namespace macsim {

WorldFileError::WorldFileError(std::string file, int line, const std::string& message)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " + message),
      file_(std::move(file)),
      line_(line),
      message_(message) {}

namespace {

using tinyxml2::XMLElement;

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

/// Reads one file's elements; knows where it is for messages.
class Reader {
 public:
  Reader(std::string file, const WarningSink& warn) : file_(std::move(file)), warn_(warn) {}

  [[noreturn]] void fail(const XMLElement* at, const std::string& message) const {
    throw WorldFileError(file_, at ? at->GetLineNum() : 0, message);
  }
  void warn(const XMLElement* at, const std::string& message) const {
    if (warn_) warn_(file_ + ":" + std::to_string(at->GetLineNum()) + ": warning: " + message);
  }

  std::string text(const XMLElement* e) const { return trim(e->GetText() ? e->GetText() : ""); }

  double number(const XMLElement* e) const {
    const std::string t = text(e);
    try {
      std::size_t used = 0;
      const double value = std::stod(t, &used);
      if (used == t.size() && std::isfinite(value)) return value;
    } catch (const std::exception&) {
    }
    fail(e, "<" + std::string(e->Name()) + "> expects a finite number, got '" + t + "'");
  }

  double positive(const XMLElement* e) const {
    const double value = number(e);
    if (value <= 0.0) {
      fail(e, "<" + std::string(e->Name()) + "> must be positive, got " + text(e));
    }
    return value;
  }

  std::vector<double> numbers(const XMLElement* e, std::size_t min_count,
                              std::size_t max_count) const {
    std::vector<double> values;
    std::stringstream stream(text(e));
    std::string item;
    while (std::getline(stream, item, ',')) {
      item = trim(item);
      try {
        std::size_t used = 0;
        const double value = std::stod(item, &used);
        if (used != item.size() || !std::isfinite(value)) throw std::invalid_argument(item);
        values.push_back(value);
      } catch (const std::exception&) {
        fail(e, "<" + std::string(e->Name()) + "> expects comma-separated numbers, got '" +
                    text(e) + "'");
      }
    }
    if (values.size() < min_count || values.size() > max_count) {
      const std::string expected = min_count == max_count
                                       ? std::to_string(min_count)
                                       : std::to_string(min_count) + " to " +
                                             std::to_string(max_count);
      fail(e, "<" + std::string(e->Name()) + "> expects " + expected + " numbers, got " +
                  std::to_string(values.size()));
    }
    return values;
  }

  Eigen::Vector3d vector3(const XMLElement* e) const {
    const auto v = numbers(e, 3, 3);
    return {v[0], v[1], v[2]};
  }

  /// ROT: roll, pitch, yaw in degrees about fixed x, y, z (applied in that order).
  Eigen::Quaterniond rotation(const XMLElement* e) const {
    const Eigen::Vector3d rpy = vector3(e) * (M_PI / 180.0);
    return Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX());
  }

  SourceLocation where(const XMLElement* e) const { return {file_, e->GetLineNum()}; }

 private:
  std::string file_;
  const WarningSink& warn_;
};

void read_physics(const Reader& r, const XMLElement* physics, PhysicsSpec& spec) {
  for (auto* e = physics->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = upper(e->Name());
    if (tag == "STEP") {
      spec.step = r.positive(e);
    } else if (tag == "GRAVITY") {
      spec.gravity = r.vector3(e);
    } else if (tag == "ITERATIONS") {
      spec.solver_iterations = static_cast<int>(r.positive(e));
    } else if (tag == "ERP") {
      spec.erp = r.positive(e);
    } else if (tag == "CFM") {
      spec.cfm = r.positive(e);
    } else if (tag == "SEED") {
      spec.seed = static_cast<uint32_t>(r.number(e));
    } else {
      r.warn(e, "unknown element <" + std::string(e->Name()) + "> in <PHYSICS> ignored");
    }
  }
}

Shape read_shape(const Reader& r, const XMLElement* e) {
  const std::string value = upper(r.text(e));
  if (value == "BOX") return Shape::Box;
  if (value == "CYLINDER") return Shape::Cylinder;
  if (value == "SPHERE") return Shape::Sphere;
  r.fail(e, "unknown shape '" + r.text(e) + "' (expected BOX, CYLINDER or SPHERE)");
}

ObjectSpec read_object(const Reader& r, const XMLElement* object) {
  ObjectSpec spec;
  spec.source = r.where(object);
  const XMLElement* dims = nullptr;
  const XMLElement* radius = nullptr;
  const XMLElement* height = nullptr;
  for (auto* e = object->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = upper(e->Name());
    if (tag == "ID") {
      spec.id = r.text(e);
    } else if (tag == "TYPE") {
      const std::string type = upper(r.text(e));
      if (type != "PORTABLE" && type != "FIXED") {
        r.fail(e, "object <TYPE> must be PORTABLE or FIXED, got '" + r.text(e) + "'");
      }
      spec.portable = type == "PORTABLE";
    } else if (tag == "SHAPE") {
      spec.shape = read_shape(r, e);
    } else if (tag == "DIMS") {
      dims = e;
    } else if (tag == "RADIUS") {
      radius = e;
    } else if (tag == "HEIGHT") {
      height = e;
    } else if (tag == "POS") {
      spec.pose.position = r.vector3(e);
    } else if (tag == "ROT") {
      spec.pose.orientation = r.rotation(e);
    } else if (tag == "DENSITY") {
      spec.density = r.positive(e);
    } else if (tag == "MASS") {
      spec.mass = r.positive(e);
    } else if (tag == "FRICTION") {
      spec.friction = r.number(e);
      if (spec.friction < 0) r.fail(e, "<FRICTION> must not be negative");
    } else if (tag == "COLOR") {
      const auto c = r.numbers(e, 3, 4);
      for (double channel : c) {
        if (channel < 0.0 || channel > 1.0) r.fail(e, "<COLOR> channels must lie in [0, 1]");
      }
      spec.color = {float(c[0]), float(c[1]), float(c[2]), c.size() == 4 ? float(c[3]) : 1.0f};
    } else if (tag == "USER_DATA") {
      spec.user_data = r.text(e);
    } else {
      r.warn(e, "unknown element <" + std::string(e->Name()) + "> in <OBJECT> ignored");
    }
  }
  if (spec.id.empty()) r.fail(object, "<OBJECT> needs an <ID>");
  switch (spec.shape) {
    case Shape::Box:
      if (!dims) r.fail(object, "box object '" + spec.id + "' needs <DIMS>x,y,z</DIMS>");
      spec.size = r.vector3(dims);
      if ((spec.size.array() <= 0.0).any()) {
        r.fail(dims, "box dimensions must be positive");
      }
      break;
    case Shape::Cylinder:
      if (!radius || !height) {
        r.fail(object, "cylinder object '" + spec.id + "' needs <RADIUS> and <HEIGHT>");
      }
      spec.size = {r.positive(radius), 0.0, r.positive(height)};
      break;
    case Shape::Sphere:
      if (!radius) r.fail(object, "sphere object '" + spec.id + "' needs <RADIUS>");
      spec.size = {r.positive(radius), 0.0, 0.0};
      break;
  }
  return spec;
}

RobotSpec read_robot(const Reader& r, const XMLElement* robot) {
  RobotSpec spec;
  spec.source = r.where(robot);
  for (auto* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = upper(e->Name());
    if (tag == "ID") {
      spec.name = r.text(e);
    } else if (tag == "TYPE") {
      spec.type = r.text(e);
    } else if (tag == "POS") {
      spec.pose.position = r.vector3(e);
    } else if (tag == "ROT") {
      spec.pose.orientation = r.rotation(e);
    } else {
      r.warn(e, "unknown element <" + std::string(e->Name()) + "> in <ROBOT> ignored");
    }
  }
  if (spec.name.empty()) r.fail(robot, "<ROBOT> needs an <ID> (its topic namespace)");
  if (spec.type.empty()) r.fail(robot, "<ROBOT> '" + spec.name + "' needs a <TYPE>");
  const bool valid_name = std::all_of(spec.name.begin(), spec.name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_';
  });
  if (!valid_name || std::isdigit(static_cast<unsigned char>(spec.name[0]))) {
    r.fail(robot, "robot <ID> '" + spec.name +
                      "' must be a topic name: letters, digits and _, not starting with a digit");
  }
  return spec;
}

/// tinyxml2's error as a sentence: what went wrong and, where it says, at which element.
std::string xml_error_message(const tinyxml2::XMLDocument& doc) {
  std::string what;
  switch (doc.ErrorID()) {
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT: what = "element not closed by its end tag"; break;
    case tinyxml2::XML_ERROR_PARSING_ELEMENT: what = "cannot parse an element"; break;
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE: what = "cannot parse an attribute"; break;
    case tinyxml2::XML_ERROR_PARSING_TEXT: what = "cannot parse text"; break;
    case tinyxml2::XML_ERROR_PARSING_COMMENT: what = "cannot parse a comment"; break;
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: what = "the document is empty"; break;
    case tinyxml2::XML_ERROR_FILE_COULD_NOT_BE_OPENED: what = "the file cannot be opened"; break;
    default: what = doc.ErrorName(); break;
  }
  // ErrorStr() ends with details such as "XMLElement name=ROBOT".
  const std::string detail = doc.ErrorStr() ? doc.ErrorStr() : "";
  const auto name = detail.find("name=");
  if (name != std::string::npos) what += " <" + detail.substr(name + 5) + ">";
  return "malformed XML: " + what;
}

WorldSpec parse(tinyxml2::XMLDocument& doc, const std::string& file, const WarningSink& warn) {
  if (doc.Error()) throw WorldFileError(file, doc.ErrorLineNum(), xml_error_message(doc));
  const Reader r(file, warn);
  const XMLElement* root = doc.RootElement();
  if (!root || upper(root->Name()) != "WORLD") {
    r.fail(root, "the root element of a world file must be <WORLD>");
  }
  WorldSpec world;
  world.file = file;
  world.name = std::filesystem::path(file).stem().string();
  std::set<std::string> ids;
  for (auto* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = upper(e->Name());
    if (tag == "NAME") {
      world.name = r.text(e);
    } else if (tag == "PHYSICS") {
      read_physics(r, e, world.physics);
    } else if (tag == "GROUND") {
      world.ground = true;
      if (auto* f = e->FirstChildElement("FRICTION")) world.ground_friction = r.number(f);
    } else if (tag == "OBJECT") {
      ObjectSpec object = read_object(r, e);
      if (!ids.insert(object.id).second) r.fail(e, "duplicate id '" + object.id + "'");
      world.objects.push_back(std::move(object));
    } else if (tag == "ROBOT") {
      RobotSpec robot = read_robot(r, e);
      if (!ids.insert(robot.name).second) r.fail(e, "duplicate id '" + robot.name + "'");
      world.robots.push_back(std::move(robot));
    } else {
      r.warn(e, "unknown element <" + std::string(e->Name()) + "> ignored");
    }
  }
  return world;
}

}  // namespace

WorldSpec load_world_file(const std::string& path, const WarningSink& warn) {
  if (!std::filesystem::is_regular_file(path)) {
    throw WorldFileError(path, 0, "no such world file");
  }
  tinyxml2::XMLDocument doc;
  doc.LoadFile(path.c_str());
  return parse(doc, path, warn);
}

WorldSpec load_world_string(const std::string& xml, const std::string& name,
                            const WarningSink& warn) {
  tinyxml2::XMLDocument doc;
  doc.Parse(xml.c_str(), xml.size());
  return parse(doc, name, warn);
}

}  // namespace macsim
