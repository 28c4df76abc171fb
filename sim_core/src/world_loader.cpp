#include "macsim/sim_core/world_loader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "macsim/sim_core/data_roots.h"
#include "macsim/sim_core/log_sink.h"
#include "macsim/sim_core/texture.h"
#include "macsim/sim_core/world_bounds.h"

namespace macsim {

WorldFileError::WorldFileError(std::string file, int line, const std::string& message)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " + message),
      file_(std::move(file)),
      line_(line),
      message_(message) {}

namespace {

namespace fs = std::filesystem;
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

/// tinyxml2's error as a sentence: what went wrong and, where it says, at which element.
std::string xml_error_message(const tinyxml2::XMLDocument& doc) {
  std::string what;
  switch (doc.ErrorID()) {
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
      what = "element not closed by its end tag";
      break;
    case tinyxml2::XML_ERROR_PARSING_ELEMENT:
      what = "cannot parse an element";
      break;
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
      what = "cannot parse an attribute";
      break;
    case tinyxml2::XML_ERROR_PARSING_TEXT:
      what = "cannot parse text";
      break;
    case tinyxml2::XML_ERROR_PARSING_COMMENT:
      what = "cannot parse a comment";
      break;
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT:
      what = "the document is empty";
      break;
    case tinyxml2::XML_ERROR_FILE_COULD_NOT_BE_OPENED:
      what = "the file cannot be opened";
      break;
    default:
      what = doc.ErrorName();
      break;
  }
  // ErrorStr() ends with details such as "XMLElement name=ROBOT".
  const std::string detail = doc.ErrorStr() ? doc.ErrorStr() : "";
  const auto name = detail.find("name=");
  if (name != std::string::npos) what += " <" + detail.substr(name + 5) + ">";
  return "malformed XML: " + what;
}

/// Reads one file's elements; knows where it is for messages.
class Reader {
 public:
  Reader(std::string file, const WorldFiles& files) : file_(std::move(file)), files_(files) {}

  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const XMLElement* at, const std::string& message) const {
    throw WorldFileError(file_, at ? at->GetLineNum() : 0, message);
  }
  void warn(const XMLElement* at, const std::string& message) const {
    log_message(LogLevel::Warning,
                file_ + ":" + std::to_string(at->GetLineNum()) + ": warning: " + message);
  }
  void unknown(const XMLElement* e, const char* parent) const {
    warn(e, "unknown element <" + std::string(e->Name()) + "> in <" + parent + "> ignored");
  }

  std::string text(const XMLElement* e) const { return trim(e->GetText() ? e->GetText() : ""); }

  std::string tag(const XMLElement* e) const { return "<" + std::string(e->Name()) + ">"; }

  /// The bytes of the file `e` names, or nothing if it is missing; a refused file fails at `e`.
  std::optional<std::string> read(const XMLElement* e, const std::string& path) const {
    try {
      return files_.read(path);
    } catch (const FileRefused& refused) {
      fail(e, refused.what());
    }
  }

  double number(const XMLElement* e) const {
    const std::string t = text(e);
    try {
      std::size_t used = 0;
      const double value = std::stod(t, &used);
      if (used == t.size() && std::isfinite(value)) return value;
    } catch (const std::exception&) {
    }
    fail(e, tag(e) + " expects a finite number, got '" + t + "'");
  }

  double positive(const XMLElement* e) const {
    const double value = number(e);
    if (value <= 0.0) fail(e, tag(e) + " must be positive, got " + text(e));
    return value;
  }

  double non_negative(const XMLElement* e) const {
    const double value = number(e);
    if (value < 0.0) fail(e, tag(e) + " must not be negative, got " + text(e));
    return value;
  }

  bool boolean(const XMLElement* e) const {
    const std::string t = upper(text(e));
    if (t == "TRUE" || t == "1" || t == "YES") return true;
    if (t == "FALSE" || t == "0" || t == "NO") return false;
    fail(e, tag(e) + " expects true or false, got '" + text(e) + "'");
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
        fail(e, tag(e) + " expects comma-separated numbers, got '" + text(e) + "'");
      }
    }
    if (values.size() < min_count || values.size() > max_count) {
      const std::string expected =
          min_count == max_count ? std::to_string(min_count)
                                 : std::to_string(min_count) + " to " + std::to_string(max_count);
      fail(e, tag(e) + " expects " + expected + " numbers, got " + std::to_string(values.size()));
    }
    return values;
  }

  Eigen::Vector3d vector3(const XMLElement* e) const {
    const auto v = numbers(e, 3, 3);
    return {v[0], v[1], v[2]};
  }

  Eigen::Vector3d positive_vector3(const XMLElement* e) const {
    const Eigen::Vector3d v = vector3(e);
    if ((v.array() <= 0.0).any()) fail(e, tag(e) + " must be positive in every axis");
    return v;
  }

  /// ROT: roll, pitch, yaw in degrees about fixed x, y, z (applied in that order).
  Eigen::Quaterniond rotation(const XMLElement* e) const {
    const Eigen::Vector3d rpy = vector3(e) * (M_PI / 180.0);
    return Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX());
  }

  Color color(const XMLElement* e) const {
    const auto c = numbers(e, 3, 4);
    for (double channel : c) {
      if (channel < 0.0 || channel > 1.0) fail(e, "<COLOR> channels must lie in [0, 1]");
    }
    return {float(c[0]), float(c[1]), float(c[2]), c.size() == 4 ? float(c[3]) : 1.0f};
  }

  /// A texture path relative to this file, checked to be a 2^n x 2^n BMP.
  std::string texture(const XMLElement* e) const {
    const fs::path relative = text(e);
    const std::string path =
        (relative.is_absolute() ? relative : fs::path(file_).parent_path() / relative)
            .lexically_normal()
            .string();
    const auto bytes = read(e, path);
    if (!bytes) fail(e, "texture file '" + path + "' does not exist");
    if (auto problem = texture_bytes_problem(path, *bytes)) fail(e, *problem);
    return path;
  }

  SourceLocation where(const XMLElement* e) const { return {file_, e->GetLineNum()}; }

 private:
  std::string file_;
  const WorldFiles& files_;
};

bool valid_id(const std::string& id) { return !bounds::id_problem(id).has_value(); }

/// What one loaded file (and its imports) contributed, for the naming conventions.
struct FileContents {
  std::map<std::string, FileContents> imports;  // by import ID
  std::vector<std::string> objects;             // full names
  std::vector<std::string> joints;              // full names
};

/// Reads a world's own settings into it: <PHYSICS> (joint force ranges, areas), <VARIATION>
/// (placements, groups) and <MATERIAL>.
class SettingsReader {
 public:
  explicit SettingsReader(WorldSpec& world) : world_(world) {}

  void read_physics(const Reader& r, const XMLElement* physics) {
    PhysicsSpec& spec = world_.physics;
    spec.source = r.where(physics);
    for (auto* e = physics->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "STEP") {
        spec.step = r.positive(e);
      } else if (tag == "GRAVITY") {
        spec.gravity = r.vector3(e);
      } else if (tag == "ITERATIONS") {
        const double iterations = r.positive(e);
        if (iterations != std::floor(iterations) || iterations > bounds::kMaxSolverIterations) {
          r.fail(e, "<ITERATIONS> must be a whole number from 1 to " +
                        std::to_string(bounds::kMaxSolverIterations) + ", got " + r.text(e));
        }
        spec.solver_iterations = static_cast<int>(iterations);
      } else if (tag == "ERP") {
        spec.erp = r.positive(e);
      } else if (tag == "CFM") {
        spec.cfm = r.positive(e);
      } else if (tag == "SEED") {
        const double seed = r.non_negative(e);
        if (seed != std::floor(seed) || seed > double(std::numeric_limits<uint32_t>::max())) {
          r.fail(e, "<SEED> must be a whole number from 0 to 4294967295, got " + r.text(e));
        }
        spec.seed = static_cast<uint32_t>(seed);
      } else {
        r.unknown(e, "PHYSICS");
      }
    }
  }

  /// x_min, y_min, x_max, y_max of a floor area, each within the coordinate bound.
  Eigen::Vector4d area(const Reader& r, const XMLElement* e) {
    const auto v = r.numbers(e, 4, 4);
    for (double value : v) {
      if (std::fabs(value) > bounds::kMaxCoordinate) {
        r.fail(e, r.tag(e) + " coordinates must lie within +-" +
                      std::to_string(int(bounds::kMaxCoordinate)) + " m");
      }
    }
    if (!(v[0] < v[2] && v[1] < v[3])) {
      r.fail(e, r.tag(e) + " expects x_min,y_min,x_max,y_max with min < max, got " + r.text(e));
    }
    return {v[0], v[1], v[2], v[3]};
  }

  /// <VARY_JOINT><JOINT>id</JOINT><MAX_FORCE>lo,hi</MAX_FORCE></VARY_JOINT>
  JointForceRange joint_force_range(const Reader& r, const XMLElement* element) {
    JointForceRange range;
    range.source = r.where(element);
    bool has_force = false;
    for (auto* e = element->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "JOINT") {
        range.joint = r.text(e);
      } else if (tag == "MAX_FORCE") {
        const auto v = r.numbers(e, 2, 2);
        if (!(v[0] >= 0 && v[0] <= v[1] && v[1] <= bounds::kMaxForce)) {
          r.fail(e, "<MAX_FORCE> expects lo,hi with 0 <= lo <= hi <= " +
                        std::to_string(int(bounds::kMaxForce)) + ", got " + r.text(e));
        }
        range.lo = v[0];
        range.hi = v[1];
        has_force = true;
      } else {
        r.unknown(e, "VARY_JOINT");
      }
    }
    if (range.joint.empty() || !has_force) {
      r.fail(element, "<VARY_JOINT> needs <JOINT> (the joints' id) and <MAX_FORCE> (lo,hi)");
    }
    return range;
  }

  /// What to place and where, as <VARIATION> and <PLACE> both say it.
  struct Placement {
    std::string& user_data;
    Eigen::Vector4d& area;
    bool& inside;
    double& clearance;
    bool has_area = false;
  };
  /// Reads `e` into `p` if it is <OBJECTS>, <AREA>, <INSIDE> or <CLEARANCE>; false otherwise.
  bool read_placement(const Reader& r, const XMLElement* e, const std::string& tag, Placement& p) {
    if (tag == "OBJECTS") {
      p.user_data = r.text(e);
    } else if (tag == "AREA") {
      p.area = area(r, e);
      p.has_area = true;
    } else if (tag == "INSIDE") {
      p.inside = r.boolean(e);
    } else if (tag == "CLEARANCE") {
      p.clearance = r.non_negative(e);
      if (p.clearance > bounds::kMaxSize) r.fail(e, "<CLEARANCE> is out of bounds");
    } else {
      return false;
    }
    return true;
  }

  /// <PLACE><OBJECTS>user data</OBJECTS><AREA>..</AREA>[<INSIDE>][<CLEARANCE>]</PLACE>
  PlaceGroup place_group(const Reader& r, const XMLElement* element) {
    PlaceGroup g;
    g.source = r.where(element);
    Placement placement{g.user_data, g.area, g.inside, g.clearance};
    for (auto* e = element->FirstChildElement(); e; e = e->NextSiblingElement()) {
      if (!read_placement(r, e, upper(e->Name()), placement)) r.unknown(e, "PLACE");
    }
    if (g.user_data.empty() || !placement.has_area) {
      r.fail(element, "<PLACE> needs <OBJECTS> (the user data of the objects to place) and <AREA>");
    }
    return g;
  }

  void read_variation(const Reader& r, const XMLElement* element) {
    VariationSpec v;
    v.source = r.where(element);
    Placement placement{v.user_data, v.area, v.inside, v.clearance};
    for (auto* e = element->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (read_placement(r, e, tag, placement)) {
        continue;
      } else if (tag == "ROBOT_AREA") {
        v.robot_area = area(r, e);
      } else if (tag == "COLOR") {
        v.colors.push_back(r.color(e));
      } else if (tag == "KEEP_COLOR") {
        v.keep_colors.push_back(r.text(e));
        if (v.keep_colors.back().empty()) r.fail(e, "<KEEP_COLOR> names a material");
      } else if (tag == "VARY_JOINT") {
        v.joint_forces.push_back(joint_force_range(r, e));
      } else if (tag == "PLACE") {
        v.groups.push_back(place_group(r, e));
      } else {
        r.unknown(e, "VARIATION");
      }
    }
    if (v.user_data.empty() || !placement.has_area) {
      r.fail(element,
             "<VARIATION> needs <OBJECTS> (the user data of the objects to place) and "
             "<AREA>");
    }
    world_.variation = std::move(v);
  }

  void read_material(const Reader& r, const XMLElement* element) {
    MaterialSpec m;
    m.source = r.where(element);
    for (auto* e = element->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "NAME") {
        m.name = r.text(e);
      } else if (tag == "FRICTION") {
        m.friction = r.non_negative(e);
      } else if (tag == "BOUNCE") {
        m.bounce = r.non_negative(e);
        if (m.bounce > 1.0) r.fail(e, "<BOUNCE> must lie in [0, 1]");
      } else if (tag == "BOUNCE_VELOCITY") {
        m.bounce_velocity = r.non_negative(e);
      } else if (tag == "DENSITY") {
        m.density = r.positive(e);
      } else {
        r.unknown(e, "MATERIAL");
      }
    }
    if (m.name.empty()) r.fail(element, "<MATERIAL> definition needs a <NAME>");
    if (const MaterialSpec* known = world_.material(m.name)) {
      const bool same = known->friction == m.friction && known->bounce == m.bounce &&
                        known->bounce_velocity == m.bounce_velocity && known->density == m.density;
      // A file imported twice defines its materials twice: fine when they agree.
      if (!same) r.fail(element, "material '" + m.name + "' is defined twice, differently");
      return;
    }
    world_.materials.push_back(m);
  }

 private:
  WorldSpec& world_;
};

/// Reads the elements a world or environment file places: <OBJECT>, <WALL>, <RAMP> (their
/// components, shapes and masses, with the world's materials), <JOINT> and <ROBOT>.
class ElementReader {
 public:
  explicit ElementReader(const WorldSpec& world) : world_(world) {}

  Shape read_shape(const Reader& r, const XMLElement* e) const {
    const std::string value = upper(r.text(e));
    if (value == "BOX") return Shape::Box;
    if (value == "CYLINDER") return Shape::Cylinder;
    if (value == "SPHERE") return Shape::Sphere;
    r.fail(e, "unknown shape '" + r.text(e) + "' (expected BOX, CYLINDER or SPHERE)");
  }

  /// Reads the shape-related child `e` of an object or component; true if it was one.
  bool read_component_field(const Reader& r, const XMLElement* e, ComponentSpec& c,
                            const XMLElement*& dims, const XMLElement*& radius,
                            const XMLElement*& height) const {
    const std::string tag = upper(e->Name());
    if (tag == "SHAPE") {
      c.shape = read_shape(r, e);
    } else if (tag == "DIMS") {
      dims = e;
    } else if (tag == "RADIUS") {
      radius = e;
    } else if (tag == "HEIGHT") {
      height = e;
    } else if (tag == "COLOR") {
      c.color = r.color(e);
    } else if (tag == "TEXTURE") {
      c.texture = r.texture(e);
    } else {
      return false;
    }
    return true;
  }

  void finish_component(const Reader& r, const XMLElement* at, const std::string& what,
                        ComponentSpec& c, const XMLElement* dims, const XMLElement* radius,
                        const XMLElement* height) const {
    switch (c.shape) {
      case Shape::Box:
        if (!dims) r.fail(at, what + " is a BOX and needs <DIMS>x,y,z</DIMS>");
        c.size = r.positive_vector3(dims);
        break;
      case Shape::Cylinder:
        if (!radius || !height) r.fail(at, what + " is a CYLINDER and needs <RADIUS> and <HEIGHT>");
        c.size = {r.positive(radius), 0.0, r.positive(height)};
        break;
      case Shape::Sphere:
        if (!radius) r.fail(at, what + " is a SPHERE and needs <RADIUS>");
        c.size = {r.positive(radius), 0.0, 0.0};
        break;
    }
  }

  ComponentSpec read_component(const Reader& r, const XMLElement* component,
                               const Color& default_color) const {
    ComponentSpec c;
    c.color = default_color;
    const XMLElement *dims = nullptr, *radius = nullptr, *height = nullptr;
    bool has_shape = false;
    for (auto* e = component->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "POS") {
        c.pose.position = r.vector3(e);
      } else if (tag == "ROT") {
        c.pose.orientation = r.rotation(e);
      } else if (read_component_field(r, e, c, dims, radius, height)) {
        has_shape |= tag == "SHAPE";
      } else {
        r.unknown(e, "COMPONENT");
      }
    }
    if (!has_shape) r.fail(component, "<COMPONENT> needs a <SHAPE>");
    finish_component(r, component, "<COMPONENT>", c, dims, radius, height);
    return c;
  }

  /// The common part of OBJECT, WALL and RAMP: id, pose, material, user apps.
  bool read_common(const Reader& r, const XMLElement* e, ObjectSpec& spec,
                   std::optional<double>& mass, std::optional<double>& density) const {
    const std::string tag = upper(e->Name());
    if (tag == "ID") {
      spec.name = r.text(e);
      if (!valid_id(spec.name)) {
        r.fail(e, "<ID> '" + spec.name + "' may hold only letters, digits, _ - and .");
      }
    } else if (tag == "POS") {
      spec.pose.position = r.vector3(e);
    } else if (tag == "ROT") {
      spec.pose.orientation = r.rotation(e);
    } else if (tag == "MATERIAL") {
      spec.material = r.text(e);
      if (!world_.material(spec.material)) {
        r.fail(e, "unknown material '" + spec.material + "' (define it with <MATERIAL><NAME>" +
                      spec.material + "</NAME>...</MATERIAL> before use)");
      }
    } else if (tag == "DENSITY") {
      density = r.positive(e);
    } else if (tag == "MASS") {
      mass = r.positive(e);
    } else if (tag == "USER_DATA") {
      spec.user_data = r.text(e);
    } else if (tag == "FROZEN") {
      spec.frozen = r.boolean(e);
    } else if (tag == "USER_APPS") {
      for (auto* a = e->FirstChildElement(); a; a = a->NextSiblingElement()) {
        const std::string app = upper(a->Name());
        if (app == "MAGNETIZABLE") {
          spec.magnetizable = r.boolean(a);
        } else if (app == "USER_COLOR") {
          spec.user_color = static_cast<int>(r.number(a));
        } else if (app == "USER_SHAPE") {
          spec.user_shape = static_cast<int>(r.number(a));
        } else {
          r.unknown(a, "USER_APPS");
        }
      }
    } else {
      return false;
    }
    return true;
  }

  void finish_mass(const Reader& r, const XMLElement* at, ObjectSpec& spec,
                   const std::optional<double>& mass, const std::optional<double>& density) const {
    if (mass && density) r.fail(at, "give <MASS> or <DENSITY>, not both");
    spec.density = density ? *density : world_.material(spec.material)->density;
    if (mass) spec.density = *mass / spec.volume();
  }

  ObjectSpec read_object(const Reader& r, const XMLElement* object) const {
    ObjectSpec spec;
    spec.source = r.where(object);
    std::optional<double> mass, density;
    ComponentSpec single;
    const XMLElement *dims = nullptr, *radius = nullptr, *height = nullptr, *shape = nullptr;
    std::vector<const XMLElement*> components;
    for (auto* e = object->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "TYPE") {
        const std::string type = upper(r.text(e));
        if (type != "PORTABLE" && type != "FIXED") {
          r.fail(e, "object <TYPE> must be PORTABLE or FIXED, got '" + r.text(e) + "'");
        }
        spec.portable = type == "PORTABLE";
      } else if (tag == "COMPONENT") {
        components.push_back(e);
      } else if (read_common(r, e, spec, mass, density)) {
      } else if (read_component_field(r, e, single, dims, radius, height)) {
        if (tag == "SHAPE") shape = e;
      } else {
        r.unknown(e, "OBJECT");
      }
    }
    if (spec.name.empty()) r.fail(object, "<OBJECT> needs an <ID>");
    if (components.empty()) {
      if (!shape) r.fail(object, "object '" + spec.name + "' needs a <SHAPE> or <COMPONENT>s");
      finish_component(r, object, "object '" + spec.name + "'", single, dims, radius, height);
      spec.components.push_back(single);
    } else {
      if (shape || dims || radius || height) {
        r.fail(object,
               "object '" + spec.name + "' has <COMPONENT>s: give shapes and sizes inside them");
      }
      for (const auto* c : components)
        spec.components.push_back(read_component(r, c, single.color));
    }
    finish_mass(r, object, spec, mass, density);
    return spec;
  }

  ObjectSpec read_wall(const Reader& r, const XMLElement* wall) const {
    ObjectSpec spec;
    spec.kind = ObjectKind::Wall;
    spec.portable = false;
    spec.source = r.where(wall);
    std::optional<double> mass, density;
    ComponentSpec box;
    box.color = {0.85f, 0.85f, 0.8f, 1.0f};
    double length = 0, height = 0, thickness = 0.1;
    for (auto* e = wall->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "LENGTH") {
        length = r.positive(e);
      } else if (tag == "HEIGHT") {
        height = r.positive(e);
      } else if (tag == "THICKNESS") {
        thickness = r.positive(e);
      } else if (tag == "COLOR") {
        box.color = r.color(e);
      } else if (tag == "TEXTURE") {
        box.texture = r.texture(e);
      } else if (!read_common(r, e, spec, mass, density)) {
        r.unknown(e, "WALL");
      }
    }
    if (spec.name.empty()) r.fail(wall, "<WALL> needs an <ID>");
    if (length <= 0 || height <= 0) {
      r.fail(wall, "wall '" + spec.name + "' needs <LENGTH> and <HEIGHT>");
    }
    box.size = {length, thickness, height};
    box.pose.position = {0, 0, height / 2};  // POS is the middle of the wall's foot
    spec.components.push_back(box);
    finish_mass(r, wall, spec, mass, density);
    return spec;
  }

  ObjectSpec read_ramp(const Reader& r, const XMLElement* ramp) const {
    ObjectSpec spec;
    spec.kind = ObjectKind::Ramp;
    spec.portable = false;
    spec.source = r.where(ramp);
    std::optional<double> mass, density;
    RampGeometry geometry;
    const XMLElement *height = nullptr, *depth = nullptr, *angle = nullptr, *width = nullptr;
    Color color{0.6f, 0.5f, 0.4f, 1.0f};
    std::string texture;
    for (auto* e = ramp->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "WIDTH") {
        width = e;
      } else if (tag == "HEIGHT") {
        height = e;
      } else if (tag == "DEPTH") {
        depth = e;
      } else if (tag == "ANGLE") {
        angle = e;
      } else if (tag == "COLOR") {
        color = r.color(e);
      } else if (tag == "TEXTURE") {
        texture = r.texture(e);
      } else if (!read_common(r, e, spec, mass, density)) {
        r.unknown(e, "RAMP");
      }
    }
    if (spec.name.empty()) r.fail(ramp, "<RAMP> needs an <ID>");
    if (!width || !angle || (height == nullptr) == (depth == nullptr)) {
      r.fail(ramp, "ramp '" + spec.name +
                       "' needs <WIDTH>, <ANGLE> (degrees) and one of <HEIGHT> or <DEPTH>");
    }
    geometry.width = r.positive(width);
    geometry.angle = r.positive(angle) * M_PI / 180.0;
    if (geometry.angle >= M_PI / 2) r.fail(angle, "<ANGLE> must lie in (0, 90) degrees");
    geometry.height = height ? r.positive(height) : r.positive(depth) * std::tan(geometry.angle);
    spec.ramp = geometry;
    ComponentSpec box = geometry.box();
    box.color = color;
    box.texture = texture;
    spec.components.push_back(box);
    finish_mass(r, ramp, spec, mass, density);
    return spec;
  }

  JointSpec read_joint(const Reader& r, const XMLElement* joint) const {
    JointSpec spec;
    spec.source = r.where(joint);
    for (auto* e = joint->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "ID") {
        spec.name = r.text(e);
      } else if (tag == "TYPE") {
        const std::string type = upper(r.text(e));
        if (type == "SLIDER") {
          spec.type = JointSpec::Type::Slider;
        } else if (type == "HINGE") {
          spec.type = JointSpec::Type::Hinge;
        } else {
          r.fail(e, "joint <TYPE> must be SLIDER or HINGE, got '" + r.text(e) + "'");
        }
      } else if (tag == "BODY1") {
        spec.body1 = r.text(e);
      } else if (tag == "BODY2") {
        spec.body2 = r.text(e);
      } else if (tag == "AXIS") {
        spec.axis = r.vector3(e);
        if (spec.axis.norm() < 1e-9) r.fail(e, "<AXIS> must not be zero");
        spec.axis.normalize();
      } else if (tag == "ANCHOR") {
        spec.anchor = r.vector3(e);
      } else if (tag == "LO") {
        spec.lo = r.number(e);
      } else if (tag == "HI") {
        spec.hi = r.number(e);
      } else if (tag == "MAX_FORCE" || tag == "MAXFORCE") {
        spec.max_force = r.non_negative(e);
      } else if (tag == "VELOCITY") {
        spec.velocity = r.number(e);
      } else {
        r.unknown(e, "JOINT");
      }
    }
    if (spec.name.empty()) r.fail(joint, "<JOINT> needs an <ID>");
    if (spec.body1.empty()) r.fail(joint, "joint '" + spec.name + "' needs a <BODY1>");
    if (spec.lo > spec.hi) r.fail(joint, "joint '" + spec.name + "' has <LO> above <HI>");
    if (spec.type == JointSpec::Type::Hinge) {
      spec.lo *= M_PI / 180.0;  // hinge stops are written in degrees
      spec.hi *= M_PI / 180.0;
    }
    return spec;
  }

  RobotSpec read_robot(const Reader& r, const XMLElement* robot) const {
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
      } else if (tag == "ENCODER_RATE") {
        spec.encoder_rate = r.positive(e);
      } else {
        r.unknown(e, "ROBOT");
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

 private:
  const WorldSpec& world_;
};

/// Loads a world file and its <IMPORT> tree into one WorldSpec.
class Loader {
 public:
  explicit Loader(const LoadOptions& options, const std::vector<MaterialSpec>& materials = {})
      : limits_(options.limits), files_(*options.files) {
    world_.materials = materials;
    if (!world_.material("default")) {
      MaterialSpec fallback;
      fallback.name = "default";
      world_.materials.insert(world_.materials.begin(), fallback);
    }
  }

  WorldSpec take() { return std::move(world_); }

  void load_root(tinyxml2::XMLDocument& doc, const std::string& file) {
    if (doc.Error()) throw WorldFileError(file, doc.ErrorLineNum(), xml_error_message(doc));
    const Reader r(file, files_);
    const XMLElement* root = doc.RootElement();
    if (!root || upper(root->Name()) != "WORLD") {
      r.fail(root, "the root element of a world file must be <WORLD>");
    }
    world_.file = file;
    world_.name = fs::path(file).stem().string();
    try {
      if (files_.read(file)) stack_.push_back(files_.identity(file));
    } catch (const FileRefused&) {  // text named after a file it is not: nothing to cycle back to
    }
    FileContents contents;
    read_children(r, root, Pose{}, "", contents, true);
  }

 private:
  std::string full_name(const std::string& prefix, const std::string& id) const {
    return prefix.empty() ? id : prefix + "/" + id;
  }

  std::size_t imported_files_ = 0;  // every <IMPORT> read so far, at any depth

  void claim_name(const Reader& r, const XMLElement* e, const std::string& name) {
    if (!names_.insert(name).second) r.fail(e, "duplicate id '" + name + "'");
  }

  // Elements allowed in both <WORLD> and <ENVIRONMENT>.
  void read_children(const Reader& r, const XMLElement* parent, const Pose& frame,
                     const std::string& prefix, FileContents& contents, bool is_world) {
    for (auto* e = parent->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (is_world && tag == "NAME") {
        world_.name = r.text(e);
      } else if (is_world && tag == "PHYSICS") {
        settings_.read_physics(r, e);
      } else if (is_world && tag == "VARIATION") {
        settings_.read_variation(r, e);
      } else if (is_world && tag == "GROUND") {
        for (auto* g = e->FirstChildElement(); g; g = g->NextSiblingElement()) {
          if (upper(g->Name()) == "FRICTION") {
            world_.ground_friction = r.non_negative(g);
          } else {
            r.unknown(g, "GROUND");
          }
        }
      } else if (tag == "MATERIAL") {
        settings_.read_material(r, e);
      } else if (tag == "OBJECT" || tag == "WALL" || tag == "RAMP") {
        ObjectSpec object = tag == "OBJECT" ? elements_.read_object(r, e)
                            : tag == "WALL" ? elements_.read_wall(r, e)
                                            : elements_.read_ramp(r, e);
        object.name = full_name(prefix, object.name);
        claim_name(r, e, object.name);
        object.pose = frame * object.pose;
        if (world_.objects.size() >= limits_.max_objects) {
          r.fail(e, "a world holds at most " + std::to_string(limits_.max_objects) +
                        " objects (LoadLimits::max_objects)");
        }
        contents.objects.push_back(object.name);
        world_.objects.push_back(std::move(object));
      } else if (tag == "JOINT") {
        JointSpec joint = elements_.read_joint(r, e);
        joint.name = full_name(prefix, joint.name);
        claim_name(r, e, joint.name);
        joint.body1 = full_name(prefix, joint.body1);
        if (!joint.body2.empty()) joint.body2 = full_name(prefix, joint.body2);
        joint.axis = frame.orientation * joint.axis;
        joint.anchor = frame.position + frame.orientation * joint.anchor;
        contents.joints.push_back(joint.name);
        world_.joints.push_back(std::move(joint));
      } else if (tag == "ROBOT") {
        RobotSpec robot = elements_.read_robot(r, e);
        claim_name(r, e, robot.name);
        robot.pose = frame * robot.pose;
        world_.robots.push_back(std::move(robot));
      } else if (tag == "IMPORT") {
        read_import(r, e, frame, prefix, contents);
      } else {
        r.unknown(e, is_world ? "WORLD" : "ENVIRONMENT");
      }
    }
  }

  void read_import(const Reader& r, const XMLElement* import, const Pose& frame,
                   const std::string& prefix, FileContents& contents) {
    std::string id, file;
    Pose pose;
    for (auto* e = import->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = upper(e->Name());
      if (tag == "ID") {
        id = r.text(e);
      } else if (tag == "NAME") {
        file = r.text(e);
      } else if (tag == "POS") {
        pose.position = r.vector3(e);
      } else if (tag == "ROT") {
        pose.orientation = r.rotation(e);
      } else {
        r.unknown(e, "IMPORT");
      }
    }
    if (id.empty()) r.fail(import, "<IMPORT> needs an <ID>");
    if (!valid_id(id))
      r.fail(import, "<IMPORT> <ID> '" + id + "' may hold only letters, digits, _ - and .");
    if (file.empty()) r.fail(import, "<IMPORT> '" + id + "' needs a <NAME> (the file to import)");
    if (contents.imports.count(id)) r.fail(import, "duplicate import id '" + id + "'");
    const fs::path path =
        fs::path(file).is_absolute() ? fs::path(file) : fs::path(r.file()).parent_path() / file;
    const std::string shown = path.lexically_normal().string();
    if (stack_.size() >= limits_.max_import_depth) {
      r.fail(import, "imports nest at most " + std::to_string(limits_.max_import_depth) +
                         " deep (import '" + id + "'; LoadLimits::max_import_depth)");
    }
    if (++imported_files_ > limits_.max_imported_files) {
      r.fail(import, "a world imports at most " + std::to_string(limits_.max_imported_files) +
                         " files in all (import '" + id +
                         "': do the imports fan out? LoadLimits::max_imported_files)");
    }
    const auto bytes = r.read(import, shown);
    if (!bytes) {
      r.fail(import, "imported file '" + shown + "' (import '" + id + "') does not exist");
    }
    const std::string canonical = files_.identity(shown);
    if (std::find(stack_.begin(), stack_.end(), canonical) != stack_.end()) {
      r.fail(import, "import cycle: '" + shown + "' imports itself (through import '" + id + "')");
    }
    tinyxml2::XMLDocument doc;
    doc.Parse(bytes->data(), bytes->size());
    if (doc.Error()) throw WorldFileError(shown, doc.ErrorLineNum(), xml_error_message(doc));
    const Reader child(shown, files_);
    const XMLElement* root = doc.RootElement();
    if (!root || upper(root->Name()) != "ENVIRONMENT") {
      child.fail(root, "the root element of an imported file must be <ENVIRONMENT>");
    }
    stack_.push_back(canonical);
    FileContents& sub = contents.imports[id];
    const std::string name = full_name(prefix, id);
    read_children(child, root, frame * pose, name, sub, false);
    stack_.pop_back();
    check_conventions(r, import, id, name, sub, prefix);
  }

  // The seed's naming conventions: a "doors" container importing door_%02d structures, each
  // importing a switch_component and a door_component. MACSim left objects outside the
  // conventions unreachable; here everything is reachable and a broken convention is a warning.
  void check_conventions(const Reader& r, const XMLElement* import, const std::string& id,
                         const std::string& name, FileContents& sub, const std::string& prefix) {
    static const std::regex door_id("door_[0-9]{2}");
    const bool in_doors_container = !prefix.empty() && fs::path(prefix).filename() == "doors";
    const bool is_door = sub.imports.count("door_component") > 0;
    if (in_doors_container && !std::regex_match(id, door_id)) {
      r.warn(import, "import '" + id +
                         "' in the doors container does not follow the door_%02d "
                         "convention; loaded and reachable as '" +
                         name + "'");
    }
    if (in_doors_container && !is_door) {
      r.warn(import, "'" + name + "' imports no door_component: loaded as plain objects");
    }
    if (!is_door) return;
    if (!in_doors_container) {
      r.warn(import, "door '" + name +
                         "' is not inside a <ID>doors</ID> container (seed "
                         "convention); loaded and reachable");
    }
    DoorSpec door;
    door.name = name;
    door.source = r.where(import);
    auto part = [&](const FileContents& c, const char* what, std::string& moving,
                    std::string& fixed, std::string& joint) {
      if (c.joints.size() != 1) {
        r.fail(import, "'" + name + "/" + what + "' must hold exactly one <JOINT>, it holds " +
                           std::to_string(c.joints.size()));
      }
      joint = c.joints.front();
      const JointSpec* j = nullptr;
      for (const auto& candidate : world_.joints) {
        if (candidate.name == joint) j = &candidate;
      }
      moving = j->body1;
      fixed = j->body2;
    };
    part(sub.imports.at("door_component"), "door_component", door.leaf, door.frame,
         door.door_joint);
    if (auto s = sub.imports.find("switch_component"); s != sub.imports.end()) {
      part(s->second, "switch_component", door.switch_platform, door.switch_base,
           door.switch_joint);
    }
    world_.doors.push_back(door);
  }

  const LoadLimits limits_;
  const WorldFiles& files_;
  WorldSpec world_;
  SettingsReader settings_{world_};
  ElementReader elements_{world_};
  std::set<std::string> names_;
  std::vector<std::string> stack_;  // canonical paths of the files being read
};

/// Checks references between elements once everything is read.
void check_references(WorldSpec& world) {
  for (const auto& joint : world.joints) {
    for (const std::string* body : {&joint.body1, &joint.body2}) {
      if (body->empty()) continue;
      if (!world.object(*body)) {
        throw WorldFileError(joint.source.file, joint.source.line,
                             "joint '" + joint.name + "' refers to unknown object '" + *body + "'");
      }
    }
    if (!world.object(joint.body1)->portable) {
      throw WorldFileError(joint.source.file, joint.source.line,
                           "joint '" + joint.name + "': <BODY1> '" + joint.body1 +
                               "' must be a PORTABLE object (it is the moving part)");
    }
  }
  auto set_kind = [&](const std::string& name, ObjectKind kind) {
    for (auto& o : world.objects) {
      if (o.name == name) o.kind = kind;
    }
  };
  for (const auto& door : world.doors) {
    set_kind(door.leaf, ObjectKind::DoorLeaf);
    set_kind(door.frame, ObjectKind::DoorFrame);
    set_kind(door.switch_platform, ObjectKind::SwitchPlatform);
    set_kind(door.switch_base, ObjectKind::SwitchBase);
  }
}

/// Parses `bytes` as the world `name` and checks it whole.
WorldSpec load_world_bytes(const std::string& bytes, const std::string& name,
                           const LoadOptions& options) {
  tinyxml2::XMLDocument doc;
  doc.Parse(bytes.data(), bytes.size());
  Loader loader(options);
  loader.load_root(doc, name);
  WorldSpec world = loader.take();
  check_references(world);
  bounds::check_world(world);
  return world;
}

}  // namespace

const WorldFiles& disk_files() {
  class DiskFiles : public WorldFiles {
   public:
    std::optional<std::string> read(const std::string& path) const override {
      std::error_code error;
      if (!fs::is_regular_file(path, error)) return std::nullopt;
      std::ifstream in(path, std::ios::binary);
      std::ostringstream bytes;
      bytes << in.rdbuf();
      if (!in) return std::nullopt;
      return bytes.str();
    }
    std::string identity(const std::string& path) const override {
      std::error_code error;
      const fs::path canonical = fs::weakly_canonical(path, error);
      return error ? fs::path(path).lexically_normal().string() : canonical.string();
    }
  };
  static const DiskFiles files;
  return files;
}

std::optional<std::string> WatchedFiles::read(const std::string& path) const {
  auto bytes = inner_.read(path);
  if (bytes && watcher_) watcher_(path, *bytes);
  return bytes;
}

void MemoryFiles::add(const std::string& path, std::string bytes) {
  files_[fs::path(path).lexically_normal().string()] = std::move(bytes);
}

std::optional<std::string> MemoryFiles::read(const std::string& path) const {
  const auto found = files_.find(fs::path(path).lexically_normal().string());
  if (found == files_.end()) return std::nullopt;
  return found->second;
}

std::string MemoryFiles::identity(const std::string& path) const {
  return fs::path(path).lexically_normal().string();
}

WorldSpec load_world_file(const std::string& path, const LoadOptions& options) {
  const auto bytes = options.files->read(path);  // a refusal is the whole answer: no line
  if (!bytes) throw WorldFileError(path, 0, "no such world file");
  return load_world_bytes(*bytes, path, options);
}

WorldSpec load_world_file(const std::string& path) { return load_world_file(path, LoadOptions{}); }

namespace {

/// An environment as the one import (of id `import_id`) of a world file in `directory`;
/// `files` reads the environment and whatever it imports.
WorldSpec load_environment(const std::string& path, const std::string& import_id,
                           const std::vector<MaterialSpec>& materials, const WorldFiles& files) {
  // A refusal is the whole answer, not an error of the import standing for the file.
  if (!files.read(path)) throw WorldFileError(path, 0, "no such environment file");
  const std::string xml =
      "<WORLD><IMPORT><ID>" + import_id + "</ID><NAME>" + path + "</NAME></IMPORT></WORLD>";
  tinyxml2::XMLDocument doc;
  doc.Parse(xml.c_str(), xml.size());
  LoadOptions options;
  options.files = &files;
  Loader loader(options, materials);
  loader.load_root(doc, (fs::path(path).parent_path() / "<import_environment>").string());
  WorldSpec world = loader.take();
  check_references(world);
  bounds::check_world(world);
  return world;
}

}  // namespace

WorldSpec load_environment_file(const std::string& path, const std::string& import_id,
                                const std::vector<MaterialSpec>& materials,
                                const WorldFiles& files) {
  // The file becomes the one import of a world file that would sit beside it.
  std::error_code error;
  const fs::path absolute = fs::absolute(path, error);
  if (error) throw WorldFileError(path, 0, "cannot resolve the path: " + error.message());
  return load_environment(absolute.string(), import_id, materials, files);
}

WorldSpec load_environment_string(const std::string& xml, const std::string& import_id,
                                  const std::vector<MaterialSpec>& materials,
                                  const std::string& name) {
  std::error_code error;
  const fs::path absolute = fs::absolute(name, error);
  if (error) throw WorldFileError(name, 0, "cannot resolve the path: " + error.message());
  MemoryFiles files;
  files.add(absolute.string(), xml);
  return load_environment(absolute.string(), import_id, materials, files);
}

WorldSpec load_world_string(const std::string& xml, const std::string& name,
                            const LoadOptions& options) {
  return load_world_bytes(xml, name, options);
}

WorldSpec load_world_string(const std::string& xml, const std::string& name) {
  return load_world_bytes(xml, name, LoadOptions{});
}

}  // namespace macsim
