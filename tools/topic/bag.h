// rosbag2 bags in the sqlite3 storage (schema version 4, metadata version 9, as ROS 2 Jazzy
// writes them): a directory with metadata.yaml and <dir>_0.db3 holding CDR samples as received.
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace macsim::topic {

/// A bag that cannot be written or read; the message names the file and what failed.
struct BagError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What a subscriber was offered by one writer, as rosbag2 stores it.
struct OfferedQos {
  bool reliable = true;
  bool transient_local = false;
};

/// A topic of a bag.
struct BagTopic {
  int id = 0;
  std::string name;  ///< ROS name, "/kurt/odom"
  std::string type;  ///< ROS type, "nav_msgs/msg/Odometry"
  std::string serialization_format = "cdr";
  std::vector<OfferedQos> offered_qos;
  std::string type_description_hash;
  std::uint64_t message_count = 0;
};

/// The offered QoS profiles as rosbag2's YAML sequence (block style).
std::string offered_qos_yaml(const std::vector<OfferedQos>& profiles);
/// Reads them back from that YAML (either the sequence or rosbag2's string form).
std::vector<OfferedQos> parse_offered_qos(const std::string& yaml);

/// Writes a bag; messages are inserted in batches on the caller's thread.
class BagWriter {
 public:
  /// Creates `dir` (which must not exist, or be empty) and its database.
  explicit BagWriter(const std::string& dir);
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  /// Adds a topic; returns its id.
  int add_topic(const std::string& ros_name, const std::string& ros_type,
                const std::vector<OfferedQos>& offered, const std::string& definition = {});
  /// Stores one message (receive time in ns since the epoch, payload with its CDR header).
  void write(int topic_id, std::int64_t timestamp_ns, const std::uint8_t* data, std::size_t size);
  /// Commits what is pending (the writer also commits every 1000 messages).
  void flush();
  /// Commits, writes metadata.yaml and the metadata row; the bag is complete.
  void close();

  std::uint64_t message_count() const { return message_count_; }
  std::uint64_t bytes_written() const { return bytes_; }
  const std::string& database_path() const { return db_path_; }

 private:
  void exec(const std::string& sql);
  std::string metadata_body() const;

  std::string dir_, db_path_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  std::vector<BagTopic> topics_;
  std::uint64_t message_count_ = 0, bytes_ = 0, pending_ = 0;
  std::int64_t first_ns_ = 0, last_ns_ = 0;
  bool closed_ = false;
};

/// Reads a bag directory (or a .db3 file).
class BagReader {
 public:
  explicit BagReader(const std::string& dir_or_db3);
  ~BagReader();
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  const std::vector<BagTopic>& topics() const { return topics_; }
  std::int64_t start_ns() const { return start_ns_; }
  std::int64_t end_ns() const { return end_ns_; }
  std::uint64_t message_count() const { return message_count_; }
  const std::string& database_path() const { return db_path_; }
  std::string ros_distro() const { return distro_; }

  /// Hands every message of the chosen topics (all if empty) to `visit` in timestamp order;
  /// stops early when visit returns false.
  void for_each(const std::set<int>& topic_ids,
                const std::function<bool(const BagTopic&, std::int64_t timestamp_ns,
                                         const std::uint8_t* data, std::size_t size)>& visit) const;

 private:
  std::string db_path_, distro_;
  sqlite3* db_ = nullptr;
  std::vector<BagTopic> topics_;
  std::int64_t start_ns_ = 0, end_ns_ = 0;
  std::uint64_t message_count_ = 0;
};

/// A summary of a bag in the manner of `ros2 bag info`.
std::string bag_summary(const BagReader& bag);

}  // namespace macsim::topic
