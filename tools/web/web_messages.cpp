#include "web_messages.h"

#include "macsim/dds/convert.h"
#include "macsim/images/image_files.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

namespace macsim::web {

namespace {

using nlohmann::json;
namespace mm = macsim_msgs::msg::dds_;

/// JSON text; strings that are not UTF-8 (names from the wire, a client's bytes) get U+FFFD
/// instead of an exception.
std::string text_of(const json& message) {
  return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

/// Metres to the millimetre: smaller frames, and nothing a browser could tell apart.
double mm3(double value) { return std::round(value * 1000.0) / 1000.0; }

json pose_array(const geometry_msgs::msg::dds_::Pose_& pose) {
  const auto& p = pose.position();
  const auto& q = pose.orientation();
  return json::array({mm3(p.x()), mm3(p.y()), mm3(p.z()), q.x(), q.y(), q.z(), q.w()});
}

json object_json(const mm::Object_& o) {
  json components = json::array();
  for (const auto& c : o.components()) {
    const auto& p = c.pose().position();
    const auto& q = c.pose().orientation();
    components.push_back({{"shape", c.shape()},
                          {"size", {c.size()[0], c.size()[1], c.size()[2]}},
                          {"position", {p.x(), p.y(), p.z()}},
                          {"orientation", {q.x(), q.y(), q.z(), q.w()}},
                          {"color", {c.color()[0], c.color()[1], c.color()[2], c.color()[3]}}});
  }
  return {{"id", o.id()},
          {"name", o.name()},
          {"kind", o.kind()},
          {"portable", o.portable()},
          {"components", components},
          {"pose", pose_array(o.pose())},
          {"ramp", {o.ramp()[0], o.ramp()[1], o.ramp()[2]}}};
}

}  // namespace

std::string scene_message(const Objects& objects, int domain, const std::string& robot) {
  json list = json::array();
  for (const auto& [id, state] : objects) list.push_back(object_json(state.object()));
  return text_of({{"type", "scene"}, {"domain", domain}, {"robot", robot}, {"objects", list}});
}

std::string update_message(const Objects& objects, double sim_time, double rtf,
                           const RobotView& robot) {
  json poses = json::object();
  for (const auto& [id, state] : objects)
    poses[std::to_string(id)] = pose_array(state.object().pose());
  json message{{"type", "update"},
               {"time", sim_time},
               {"rtf", std::round(rtf * 100) / 100},
               {"objects", poses}};
  if (robot.known) {
    json pose = json::array();
    for (double v : robot.pose) pose.push_back(v);
    message["robot"] = {{"pose", pose},
                        {"crane", {robot.slew, robot.lift, robot.hoist}},
                        {"magnet", robot.magnet},
                        {"held", robot.held}};
  }
  return text_of(message);
}

std::string scan_message(const sensor_msgs::msg::dds_::LaserScan_& scan) {
  json ranges = json::array();
  for (float r : scan.ranges()) {
    if (std::isfinite(r) && r >= scan.range_min() && r <= scan.range_max())
      ranges.push_back(mm3(r));
    else
      ranges.push_back(nullptr);
  }
  return text_of({{"type", "scan"},
                  {"stamp", client::stamp_seconds(scan.header())},
                  {"frame", scan.header().frame_id()},
                  {"angle_min", scan.angle_min()},
                  {"angle_increment", scan.angle_increment()},
                  {"ranges", ranges}});
}

std::string cloud_message(const client::Cloud& cloud, std::size_t max_points) {
  const std::size_t every = max_points == 0 ? cloud.points.size() + 1
                                            : (cloud.points.size() + max_points - 1) / max_points;
  json points = json::array();
  for (std::size_t i = 0; i < cloud.points.size(); i += std::max<std::size_t>(1, every)) {
    const auto& p = cloud.points[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    points.push_back(mm3(p[0]));
    points.push_back(mm3(p[1]));
    points.push_back(mm3(p[2]));
  }
  return text_of({{"type", "cloud"}, {"stamp", cloud.stamp}, {"points", points}});
}

std::string image_frame(char eye, const cv::Mat& bgr, int quality) {
  if (bgr.empty()) return {};
  const std::vector<unsigned char> jpeg = images::encode_jpeg(bgr, quality);
  if (jpeg.empty()) return {};
  std::string frame(1, eye);
  frame.append(jpeg.begin(), jpeg.end());
  return frame;
}

std::array<double, 3> odom_in_world(const geometry_msgs::msg::dds_::Pose_& truth,
                                    const geometry_msgs::msg::dds_::Pose_& odom) {
  const double yaw = dds::yaw_of(truth.orientation()) - dds::yaw_of(odom.orientation());
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double ox = odom.position().x(), oy = odom.position().y();
  return {truth.position().x() - (c * ox - s * oy), truth.position().y() - (s * ox + c * oy), yaw};
}

std::string plan_message(const plan_msgs::msg::dds_::Plan_& plan, const std::array<double, 3>& odom) {
  static const char* const kStatus[] = {"to do", "under way", "as predicted", "not as predicted"};
  json steps = json::array();
  for (const auto& step : plan.steps()) {
    steps.push_back({{"action", step.action()},
                     {"predicted", step.predicted()},
                     {"probability", std::round(step.probability() * 1000.0) / 1000.0},
                     {"perceived", step.perceived()},
                     {"status", step.status() < 4 ? kStatus[step.status()] : "?"}});
  }
  const double c = std::cos(odom[2]), s = std::sin(odom[2]);
  json things = json::array();
  for (const auto& t : plan.things()) {
    things.push_back({{"name", t.name()},
                      {"label", t.label()},
                      {"confidence", std::round(t.confidence() * 100.0) / 100.0},
                      {"position", {mm3(odom[0] + c * t.x() - s * t.y()), mm3(odom[1] + s * t.x() + c * t.y())}}});
  }
  return text_of({{"type", "plan"},
                  {"goal", plan.goal()},
                  {"round", plan.round()},
                  {"current", plan.current()},
                  {"outcome", plan.outcome()},
                  {"steps", steps},
                  {"things", things}});
}

std::string answer(const std::string& text, int domain, const std::string& robot) {
  auto error = [](const std::string& message) {
    return text_of({{"type", "error"}, {"message", message}});
  };
  const json request = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (request.is_discarded()) return error("not JSON: " + text.substr(0, 80));
  if (!request.is_object() || !request.contains("type") || !request["type"].is_string())
    return error("a message is a JSON object with a string \"type\"");
  if (request["type"] == "hello") {
    return text_of({{"type", "hello"}, {"domain", domain}, {"robot", robot}});
  }
  return error("unknown message type '" + request["type"].get<std::string>() + "'");
}

}  // namespace macsim::web
