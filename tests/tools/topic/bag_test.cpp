// rosbag2 bags: the schema ROS 2 Jazzy's sqlite3 storage has, metadata it can read, messages
// back in time order.
#include "bag.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

#include "support/child_process.h"

namespace macsim::topic {
namespace {

std::vector<std::string> schema_of(const std::string& db) {
  sqlite3* handle = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(handle, "SELECT sql FROM sqlite_master ORDER BY rowid;", -1, &stmt, nullptr);
  std::vector<std::string> out;
  while (sqlite3_step(stmt) == SQLITE_ROW) {
    out.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)));
  }
  sqlite3_finalize(stmt);
  sqlite3_close(handle);
  return out;
}

TEST(Bag, HasRosbag2sSqliteSchemaAndMetadata) {
  test::TempDir dir("bag_schema");
  const std::string path = dir.path() + "/run";
  {
    BagWriter bag(path);
    const int clock = bag.add_topic("/clock", "rosgraph_msgs/msg/Clock", {{true, false}});
    const int odom = bag.add_topic("/kurt/odom", "nav_msgs/msg/Odometry", {{false, false}});
    const std::vector<std::uint8_t> a{0, 1, 0, 0, 1, 2, 3, 4}, b{0, 1, 0, 0, 9};
    bag.write(clock, 2000, a.data(), a.size());
    bag.write(odom, 1000, b.data(), b.size());
    bag.write(clock, 3000, a.data(), a.size());
    bag.close();
  }
  ASSERT_TRUE(std::filesystem::exists(path + "/run_0.db3"));
  // rosbag2_storage_sqlite3, schema version 4
  EXPECT_EQ(schema_of(path + "/run_0.db3"),
            (std::vector<std::string>{
                "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY,ros_distro TEXT NOT NULL)",
                "CREATE TABLE metadata(id INTEGER PRIMARY KEY,metadata_version INTEGER NOT "
                "NULL,metadata TEXT NOT NULL)",
                "CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT "
                "NULL,serialization_format TEXT NOT NULL,offered_qos_profiles TEXT NOT "
                "NULL,type_description_hash TEXT NOT NULL)",
                "CREATE TABLE message_definitions(id INTEGER PRIMARY KEY,topic_type TEXT NOT "
                "NULL,encoding TEXT NOT NULL,encoded_message_definition TEXT NOT "
                "NULL,type_description_hash TEXT NOT NULL)",
                "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp "
                "INTEGER NOT NULL, data BLOB NOT NULL)",
                "CREATE INDEX timestamp_idx ON messages (timestamp ASC)"}));
  const YAML::Node meta = YAML::LoadFile(path + "/metadata.yaml")["rosbag2_bagfile_information"];
  EXPECT_EQ(meta["version"].as<int>(), 9);
  EXPECT_EQ(meta["storage_identifier"].as<std::string>(), "sqlite3");
  EXPECT_EQ(meta["message_count"].as<int>(), 3);
  EXPECT_EQ(meta["duration"]["nanoseconds"].as<long>(), 2000);
  EXPECT_EQ(meta["starting_time"]["nanoseconds_since_epoch"].as<long>(), 1000);
  EXPECT_EQ(meta["relative_file_paths"][0].as<std::string>(), "run_0.db3");
  EXPECT_EQ(meta["files"][0]["message_count"].as<int>(), 3);
  EXPECT_EQ(meta["ros_distro"].as<std::string>(), "jazzy");
  EXPECT_EQ(meta["compression_format"].as<std::string>(), "");
  const YAML::Node first = meta["topics_with_message_count"][0];
  EXPECT_EQ(first["message_count"].as<int>(), 2);
  EXPECT_EQ(first["topic_metadata"]["name"].as<std::string>(), "/clock");
  EXPECT_EQ(first["topic_metadata"]["type"].as<std::string>(), "rosgraph_msgs/msg/Clock");
  EXPECT_EQ(first["topic_metadata"]["serialization_format"].as<std::string>(), "cdr");
  const YAML::Node qos = first["topic_metadata"]["offered_qos_profiles"][0];
  EXPECT_EQ(qos["reliability"].as<std::string>(), "reliable");
  EXPECT_EQ(qos["durability"].as<std::string>(), "volatile");
  EXPECT_EQ(qos["deadline"]["sec"].as<long>(), 9223372036L);

  BagReader reader(path);
  EXPECT_EQ(reader.message_count(), 3u);
  EXPECT_EQ(reader.ros_distro(), "jazzy");
  ASSERT_EQ(reader.topics().size(), 2u);
  EXPECT_FALSE(reader.topics()[1].offered_qos.at(0).reliable);
  std::vector<std::int64_t> times;
  reader.for_each({}, [&](const BagTopic&, std::int64_t t, const std::uint8_t* data, std::size_t n) {
    times.push_back(t);
    EXPECT_EQ(data[1], 1);
    EXPECT_GE(n, 5u);
    return true;
  });
  EXPECT_EQ(times, (std::vector<std::int64_t>{1000, 2000, 3000}));
  EXPECT_NE(bag_summary(reader).find("Topic: /kurt/odom | Type: nav_msgs/msg/Odometry | Count: 1"),
            std::string::npos)
      << bag_summary(reader);
}

TEST(Bag, RefusesToOverwriteAndNamesWhatIsNotABag) {
  test::TempDir dir("bag_refuse");
  std::ofstream(dir.path() + "/something") << "x";
  try {
    BagWriter bag(dir.path());
    FAIL() << "wrote into a directory that was not empty";
  } catch (const BagError& e) {
    EXPECT_NE(std::string(e.what()).find("exists and is not an empty directory"),
              std::string::npos);
  }
  EXPECT_THROW(BagReader(dir.path()), BagError);  // no .db3
  std::ofstream(dir.path() + "/fake.db3") << "not sqlite at all, just text";
  EXPECT_THROW(BagReader(dir.path() + "/fake.db3"), BagError);
}

}  // namespace
}  // namespace macsim::topic
