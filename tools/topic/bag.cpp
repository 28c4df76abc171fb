#include "bag.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace macsim::topic {

namespace fs = std::filesystem;

namespace {

// rosbag2_storage_sqlite3's schema, version 4 (what Jazzy writes and reads).
const char* const kSchema[] = {
    "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY,ros_distro TEXT NOT NULL);",
    "CREATE TABLE metadata(id INTEGER PRIMARY KEY,metadata_version INTEGER NOT NULL,metadata TEXT "
    "NOT NULL);",
    "CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT NULL,"
    "serialization_format TEXT NOT NULL,offered_qos_profiles TEXT NOT NULL,type_description_hash "
    "TEXT NOT NULL);",
    "CREATE TABLE message_definitions(id INTEGER PRIMARY KEY,topic_type TEXT NOT NULL,encoding "
    "TEXT NOT NULL,encoded_message_definition TEXT NOT NULL,type_description_hash TEXT NOT NULL);",
    "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER NOT "
    "NULL, data BLOB NOT NULL);",
    "CREATE INDEX timestamp_idx ON messages (timestamp ASC);",
};
constexpr int kSchemaVersion = 4;
constexpr int kMetadataVersion = 9;
constexpr const char* kDistro = "jazzy";

YAML::Node infinite() {
  YAML::Node d;
  d["sec"] = 9223372036LL;
  d["nsec"] = 854775807LL;
  return d;
}

YAML::Node qos_node(const std::vector<OfferedQos>& profiles) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (const auto& p : profiles) {
    YAML::Node q;
    q["history"] = "unknown";  // discovery does not carry the history (rosbag2 writes the same)
    q["depth"] = 0;
    q["reliability"] = p.reliable ? "reliable" : "best_effort";
    q["durability"] = p.transient_local ? "transient_local" : "volatile";
    q["deadline"] = infinite();
    q["lifespan"] = infinite();
    q["liveliness"] = "automatic";
    q["liveliness_lease_duration"] = infinite();
    q["avoid_ros_namespace_conventions"] = false;
    list.push_back(q);
  }
  return list;
}

YAML::Node nanoseconds(const char* key, std::int64_t value) {
  YAML::Node n;
  n[key] = value;
  return n;
}

[[noreturn]] void fail(sqlite3* db, const std::string& path, const std::string& what) {
  throw BagError(path + ": " + what + ": " + (db ? sqlite3_errmsg(db) : "cannot open"));
}

}  // namespace

std::string offered_qos_yaml(const std::vector<OfferedQos>& profiles) {
  if (profiles.empty()) return "";
  YAML::Emitter out;
  out << qos_node(profiles);
  return out.c_str();
}

std::vector<OfferedQos> parse_offered_qos(const std::string& yaml) {
  std::vector<OfferedQos> out;
  if (yaml.empty()) return out;
  YAML::Node list = YAML::Load(yaml);
  if (list.IsScalar()) list = YAML::Load(list.Scalar());  // rosbag2 before v9: a string
  for (const auto& q : list) {
    OfferedQos p;
    const std::string reliability = q["reliability"] ? q["reliability"].as<std::string>() : "";
    const std::string durability = q["durability"] ? q["durability"].as<std::string>() : "";
    p.reliable = reliability != "best_effort" && reliability != "2";
    p.transient_local = durability == "transient_local" || durability == "1";
    out.push_back(p);
  }
  return out;
}

BagWriter::BagWriter(const std::string& dir) : dir_(dir) {
  std::error_code ec;
  if (fs::exists(dir_) && !(fs::is_directory(dir_) && fs::is_empty(dir_))) {
    throw BagError(dir_ + ": exists and is not an empty directory (choose a new bag directory)");
  }
  fs::create_directories(dir_, ec);
  if (ec) throw BagError(dir_ + ": cannot create the directory: " + ec.message());
  const std::string base = fs::path(dir_).lexically_normal().filename().string().empty()
                               ? fs::path(dir_).lexically_normal().parent_path().filename().string()
                               : fs::path(dir_).lexically_normal().filename().string();
  db_path_ = (fs::path(dir_) / (base + "_0.db3")).string();
  if (sqlite3_open(db_path_.c_str(), &db_) != SQLITE_OK) fail(db_, db_path_, "cannot open");
  exec("PRAGMA journal_mode=MEMORY;");
  exec("PRAGMA synchronous=OFF;");
  for (const char* sql : kSchema) exec(sql);
  exec("INSERT INTO schema (schema_version, ros_distro) VALUES (" + std::to_string(kSchemaVersion) +
       ", '" + kDistro + "');");
  if (sqlite3_prepare_v2(db_, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?);",
                         -1, &insert_, nullptr) != SQLITE_OK) {
    fail(db_, db_path_, "cannot prepare the insert");
  }
  exec("BEGIN TRANSACTION;");
}

BagWriter::~BagWriter() {
  try {
    close();
  } catch (...) {  // a destructor must not throw; close() reports errors when called itself
  }
  if (insert_) sqlite3_finalize(insert_);
  if (db_) sqlite3_close(db_);
}

void BagWriter::exec(const std::string& sql) {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    std::string message = error ? error : "?";
    sqlite3_free(error);
    throw BagError(db_path_ + ": " + message + " in: " + sql.substr(0, 80));
  }
}

int BagWriter::add_topic(const std::string& ros_name, const std::string& ros_type,
                         const std::vector<OfferedQos>& offered, const std::string& definition) {
  BagTopic topic;
  topic.id = static_cast<int>(topics_.size()) + 1;
  topic.name = ros_name;
  topic.type = ros_type;
  topic.offered_qos = offered;
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db_,
                     "INSERT INTO topics (id, name, type, serialization_format, "
                     "offered_qos_profiles, type_description_hash) VALUES (?, ?, ?, ?, ?, ?);",
                     -1, &stmt, nullptr);
  const std::string qos = offered_qos_yaml(offered);
  sqlite3_bind_int(stmt, 1, topic.id);
  sqlite3_bind_text(stmt, 2, ros_name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(stmt, 3, ros_type.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(stmt, 4, topic.serialization_format.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(stmt, 5, qos.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(stmt, 6, "", -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(stmt);
  sqlite3_finalize(stmt);
  if (rc != SQLITE_DONE) fail(db_, db_path_, "cannot add topic " + ros_name);
  bool defined = false;
  for (const auto& t : topics_) defined = defined || t.type == ros_type;
  if (!defined) {
    sqlite3_prepare_v2(db_,
                       "INSERT INTO message_definitions (topic_type, encoding, "
                       "encoded_message_definition, type_description_hash) VALUES (?, ?, ?, '');",
                       -1, &stmt, nullptr);
    sqlite3_bind_text(stmt, 1, ros_type.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(stmt, 2, definition.empty() ? "" : "ros2msg", -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(stmt, 3, definition.c_str(), -1, SQLITE_TRANSIENT);
    const int rc2 = sqlite3_step(stmt);
    sqlite3_finalize(stmt);
    if (rc2 != SQLITE_DONE) fail(db_, db_path_, "cannot add the definition of " + ros_type);
  }
  topics_.push_back(topic);
  return topic.id;
}

void BagWriter::write(int topic_id, std::int64_t timestamp_ns, const std::uint8_t* data,
                      std::size_t size) {
  if (closed_) throw BagError(db_path_ + ": written after close");
  if (topic_id < 1 || topic_id > static_cast<int>(topics_.size())) {
    throw BagError(db_path_ + ": no topic id " + std::to_string(topic_id));
  }
  sqlite3_bind_int(insert_, 1, topic_id);
  sqlite3_bind_int64(insert_, 2, timestamp_ns);
  sqlite3_bind_blob(insert_, 3, data, static_cast<int>(size), SQLITE_STATIC);
  const int rc = sqlite3_step(insert_);
  sqlite3_reset(insert_);
  if (rc != SQLITE_DONE) fail(db_, db_path_, "cannot store a message");
  if (message_count_ == 0 || timestamp_ns < first_ns_) first_ns_ = timestamp_ns;
  if (message_count_ == 0 || timestamp_ns > last_ns_) last_ns_ = timestamp_ns;
  ++message_count_;
  bytes_ += size;
  ++topics_[static_cast<std::size_t>(topic_id - 1)].message_count;
  if (++pending_ >= 1000) flush();
}

void BagWriter::flush() {
  if (closed_ || pending_ == 0) return;
  exec("COMMIT;");
  exec("BEGIN TRANSACTION;");
  pending_ = 0;
}

std::string BagWriter::metadata_body() const {
  YAML::Node m;
  m["version"] = kMetadataVersion;
  m["storage_identifier"] = "sqlite3";
  m["duration"] = nanoseconds("nanoseconds", last_ns_ - first_ns_);
  m["starting_time"] = nanoseconds("nanoseconds_since_epoch", first_ns_);
  m["message_count"] = message_count_;
  YAML::Node topics(YAML::NodeType::Sequence);
  for (const auto& t : topics_) {
    YAML::Node entry, meta;
    meta["name"] = t.name;
    meta["type"] = t.type;
    meta["serialization_format"] = t.serialization_format;
    meta["offered_qos_profiles"] = qos_node(t.offered_qos);
    meta["type_description_hash"] = t.type_description_hash;
    entry["topic_metadata"] = meta;
    entry["message_count"] = t.message_count;
    topics.push_back(entry);
  }
  m["topics_with_message_count"] = topics;
  m["compression_format"] = "";
  m["compression_mode"] = "";
  const std::string file = fs::path(db_path_).filename().string();
  m["relative_file_paths"].push_back(file);
  YAML::Node f;
  f["path"] = file;
  f["starting_time"] = nanoseconds("nanoseconds_since_epoch", first_ns_);
  f["duration"] = nanoseconds("nanoseconds", last_ns_ - first_ns_);
  f["message_count"] = message_count_;
  m["files"].push_back(f);
  m["custom_data"] = YAML::Node(YAML::NodeType::Null);
  m["ros_distro"] = kDistro;
  YAML::Emitter out;
  out << m;
  return out.c_str();
}

void BagWriter::close() {
  if (closed_) return;
  closed_ = true;
  exec("COMMIT;");
  const std::string body = metadata_body();
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db_, "INSERT INTO metadata (metadata_version, metadata) VALUES (?, ?);", -1,
                     &stmt, nullptr);
  sqlite3_bind_int(stmt, 1, kMetadataVersion);
  sqlite3_bind_text(stmt, 2, body.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(stmt);
  sqlite3_finalize(stmt);
  if (rc != SQLITE_DONE) fail(db_, db_path_, "cannot store the metadata");
  YAML::Node top;
  top["rosbag2_bagfile_information"] = YAML::Load(body);
  YAML::Emitter out;
  out << top;
  std::ofstream file(fs::path(dir_) / "metadata.yaml");
  file << out.c_str() << "\n";
  if (!file) throw BagError(dir_ + "/metadata.yaml: cannot write");
}

BagReader::BagReader(const std::string& path) {
  if (fs::is_directory(path)) {
    for (const auto& entry : fs::directory_iterator(path)) {
      if (entry.path().extension() == ".db3") db_path_ = entry.path().string();
    }
    if (db_path_.empty()) throw BagError(path + ": no .db3 file in this directory (not a bag)");
  } else {
    db_path_ = path;
  }
  if (!fs::exists(db_path_)) throw BagError(db_path_ + ": no such bag");
  if (sqlite3_open_v2(db_path_.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    fail(db_, db_path_, "cannot open");
  }
  sqlite3_stmt* stmt = nullptr;
  if (sqlite3_prepare_v2(db_, "SELECT ros_distro FROM schema;", -1, &stmt, nullptr) == SQLITE_OK &&
      sqlite3_step(stmt) == SQLITE_ROW) {
    distro_ = reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0));
  }
  sqlite3_finalize(stmt);
  if (sqlite3_prepare_v2(db_,
                         "SELECT id, name, type, serialization_format, offered_qos_profiles FROM "
                         "topics ORDER BY id;",
                         -1, &stmt, nullptr) != SQLITE_OK) {
    fail(db_, db_path_, "not a rosbag2 sqlite3 bag (no topics table)");
  }
  while (sqlite3_step(stmt) == SQLITE_ROW) {
    BagTopic t;
    t.id = sqlite3_column_int(stmt, 0);
    t.name = reinterpret_cast<const char*>(sqlite3_column_text(stmt, 1));
    t.type = reinterpret_cast<const char*>(sqlite3_column_text(stmt, 2));
    t.serialization_format = reinterpret_cast<const char*>(sqlite3_column_text(stmt, 3));
    try {
      t.offered_qos =
          parse_offered_qos(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 4)));
    } catch (const YAML::Exception& e) {
      sqlite3_finalize(stmt);
      throw BagError(db_path_ + ": topic " + t.name + ": unreadable offered QoS: " + e.what());
    }
    topics_.push_back(t);
  }
  sqlite3_finalize(stmt);
  sqlite3_prepare_v2(db_,
                     "SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) FROM messages "
                     "GROUP BY topic_id;",
                     -1, &stmt, nullptr);
  bool first = true;
  while (sqlite3_step(stmt) == SQLITE_ROW) {
    const int id = sqlite3_column_int(stmt, 0);
    const auto count = static_cast<std::uint64_t>(sqlite3_column_int64(stmt, 1));
    const std::int64_t lo = sqlite3_column_int64(stmt, 2), hi = sqlite3_column_int64(stmt, 3);
    for (auto& t : topics_) {
      if (t.id == id) t.message_count = count;
    }
    message_count_ += count;
    start_ns_ = first ? lo : std::min(start_ns_, lo);
    end_ns_ = first ? hi : std::max(end_ns_, hi);
    first = false;
  }
  sqlite3_finalize(stmt);
}

BagReader::~BagReader() {
  if (db_) sqlite3_close(db_);
}

void BagReader::for_each(const std::set<int>& topic_ids,
                         const std::function<bool(const BagTopic&, std::int64_t,
                                                  const std::uint8_t*, std::size_t)>& visit) const {
  std::map<int, const BagTopic*> by_id;
  for (const auto& t : topics_) by_id[t.id] = &t;
  sqlite3_stmt* stmt = nullptr;
  if (sqlite3_prepare_v2(db_,
                         "SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id;",
                         -1, &stmt, nullptr) != SQLITE_OK) {
    fail(db_, db_path_, "cannot read the messages");
  }
  while (sqlite3_step(stmt) == SQLITE_ROW) {
    const int id = sqlite3_column_int(stmt, 0);
    if (!topic_ids.empty() && topic_ids.count(id) == 0) continue;
    auto topic = by_id.find(id);
    if (topic == by_id.end()) continue;
    const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt, 2));
    const auto size = static_cast<std::size_t>(sqlite3_column_bytes(stmt, 2));
    if (!visit(*topic->second, sqlite3_column_int64(stmt, 1), data, size)) break;
  }
  sqlite3_finalize(stmt);
}

std::string bag_summary(const BagReader& bag) {
  std::ostringstream out;
  const double duration = static_cast<double>(bag.end_ns() - bag.start_ns()) * 1e-9;
  std::error_code ec;
  const auto size = std::filesystem::file_size(bag.database_path(), ec);
  out << "Files:             " << std::filesystem::path(bag.database_path()).filename().string()
      << "\n";
  out << "Bag size:          " << std::fixed << std::setprecision(1)
      << (ec ? 0.0 : static_cast<double>(size) / (1024.0 * 1024.0)) << " MiB\n";
  out << "Storage id:        sqlite3\n";
  out << "ROS Distro:        " << bag.ros_distro() << "\n";
  out << "Duration:          " << std::setprecision(3) << duration << "s\n";
  out << "Start:             " << std::setprecision(9) << static_cast<double>(bag.start_ns()) * 1e-9
      << "\n";
  out << "End:               " << static_cast<double>(bag.end_ns()) * 1e-9 << "\n";
  out << "Messages:          " << bag.message_count() << "\n";
  out << "Topic information: ";
  bool first = true;
  for (const auto& t : bag.topics()) {
    out << (first ? "" : "                   ") << "Topic: " << t.name << " | Type: " << t.type
        << " | Count: " << t.message_count << " | Serialization Format: " << t.serialization_format
        << "\n";
    first = false;
  }
  if (first) out << "\n";
  return out.str();
}

}  // namespace macsim::topic
