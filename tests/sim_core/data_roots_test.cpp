// DataRoots: files under the roots are read; a path outside (by `..`, a symbolic link, or
// plainly) gets one answer whether it exists or not; special files are refused unopened; the
// size cap holds; the world's operations and the loader answer with the same refusal.
#include "macsim/images/image_files.h"
#include "macsim/sim_core/data_roots.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "macsim/sim_core/world.h"
#include "macsim/sim_core/world_loader.h"
#include "support/open_watch.h"

namespace macsim {
namespace {

namespace fs = std::filesystem;

void write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

/// root/ (the only root) and outside/ beside it, in a fresh temporary folder.
class DataRootsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    base_ = fs::temp_directory_path() /
            ("macsim_roots_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(base_);
    root_ = base_ / "root";
    outside_ = base_ / "outside";
    write(root_ / "inside.xml", "<ENVIRONMENT/>");
    write(root_ / "sub" / "deeper.xml", "deeper");
    write(outside_ / "secret.xml", "secret");
    fs::create_symlink(outside_ / "secret.xml", root_ / "link_out.xml");
    fs::create_symlink(root_ / "inside.xml", root_ / "link_in.xml");
    fs::create_symlink(outside_ / "gone.xml", root_ / "dangling.xml");
    ASSERT_EQ(::mkfifo((root_ / "fifo.xml").c_str(), 0600), 0);
    roots_ = std::make_shared<DataRoots>(std::vector<std::string>{root_.string()});
    fifo_watch_ = std::make_unique<test::OpenWatch>(std::vector<std::string>{(root_ / "fifo.xml").string()});
    ASSERT_TRUE(fifo_watch_->watching());
  }
  void TearDown() override { fs::remove_all(base_); }

  /// The refusal of `path`, with the path itself taken out (what is left must not depend on it).
  std::string refusal(const std::string& path) const {
    try {
      roots_->read(path);
    } catch (const FileRefused& e) {
      std::string what = e.what();
      if (const auto at = what.find(path); at != std::string::npos) what.erase(at, path.size());
      return what;
    }
    return "read";
  }
  /// True if anyone opened the FIFO since the last look.
  bool fifo_opened() { return fifo_watch_->opened(); }

  fs::path base_, root_, outside_;
  std::shared_ptr<DataRoots> roots_;
  std::unique_ptr<test::OpenWatch> fifo_watch_;
};

TEST_F(DataRootsTest, ReadsFilesUnderARootAndSaysWhenOneIsMissing) {
  EXPECT_EQ(roots_->read((root_ / "inside.xml").string()), "<ENVIRONMENT/>");
  EXPECT_EQ(roots_->read((root_ / "sub" / ".." / "sub" / "deeper.xml").string()), "deeper");
  EXPECT_EQ(roots_->read((root_ / "link_in.xml").string()), "<ENVIRONMENT/>");
  EXPECT_EQ(roots_->read((root_ / "missing.xml").string()), std::nullopt);
  EXPECT_EQ(roots_->read((root_ / "nofolder" / "missing.xml").string()), std::nullopt);
  EXPECT_TRUE(roots_->contains((root_ / "missing.xml").string()));
  EXPECT_EQ(roots_->folders(), std::vector<fs::path>{fs::canonical(root_)});
}

TEST_F(DataRootsTest, WatchedRootsTellEveryFileReadAndRootsOfFilesOnlyNeverReadTheDisk) {
  std::vector<std::pair<std::string, std::string>> seen;
  const auto watched = roots_->watched(
      [&](const std::string& path, const std::string& bytes) { seen.emplace_back(path, bytes); });
  const std::string inside = (root_ / "inside.xml").string();
  EXPECT_EQ(watched->read(inside), "<ENVIRONMENT/>");
  EXPECT_EQ(watched->read((root_ / "missing.xml").string()), std::nullopt);
  EXPECT_THROW(watched->read((outside_ / "secret.xml").string()), FileRefused);
  ASSERT_EQ(seen.size(), 1u);  // what was read, as asked: not the missing or refused ones
  EXPECT_EQ(seen[0], std::make_pair(inside, std::string("<ENVIRONMENT/>")));
  EXPECT_EQ(watched->folders(), roots_->folders());
  // Roots of in-memory files: what they hold, by its path, and nothing of the disk.
  auto files = std::make_shared<MemoryFiles>();
  files->add("worlds/held.xml", "held");
  const auto only = DataRoots::only(files);
  EXPECT_EQ(only->read("worlds/./held.xml"), "held");
  EXPECT_TRUE(only->contains("worlds/held.xml"));
  EXPECT_FALSE(only->contains(inside));
  EXPECT_EQ(only->read(inside), std::nullopt);  // on disk, but not held
  EXPECT_TRUE(only->restricted());
  EXPECT_TRUE(only->folders().empty());
}

TEST_F(DataRootsTest, EveryWayOutGetsTheSameAnswerWhetherTheFileExistsOrNot) {
  const std::string expected = refusal((outside_ / "secret.xml").string());
  EXPECT_NE(expected, "read");
  EXPECT_NE(expected.find("is outside the folders this simulator reads files from"),
            std::string::npos)
      << expected;
  for (const fs::path& path :
       {outside_ / "missing.xml", outside_ / "nofolder" / "missing.xml",
        root_ / ".." / "outside" / "secret.xml", root_ / ".." / "outside" / "missing.xml",
        root_ / "link_out.xml", root_ / "dangling.xml", fs::path("/dev/zero"),
        fs::path("/proc/self/environ"), fs::path("/etc/hostname"), fs::path("/nonexistent")}) {
    EXPECT_EQ(refusal(path.string()), expected) << path;
    EXPECT_FALSE(roots_->contains(path.string()) && path.filename() != "dangling.xml") << path;
  }
  // Relative paths are taken from the working folder: outside the root too.
  EXPECT_EQ(refusal("secret.xml"), expected);
}

TEST_F(DataRootsTest, SpecialFilesAreRefusedWithoutBeingOpened) {
  const std::string answer = refusal((root_ / "fifo.xml").string());
  EXPECT_NE(answer.find("is not a regular file"), std::string::npos) << answer;
  EXPECT_FALSE(fifo_opened());
  EXPECT_NE(refusal(root_.string()).find("is not a regular file"), std::string::npos);
  // Even with no roots, the kernel's files and devices are never read.
  const auto anywhere = DataRoots::anywhere();
  EXPECT_FALSE(anywhere->restricted());
  for (const char* special : {"/dev/zero", "/dev/urandom", "/proc/self/environ", "/sys/kernel"}) {
    EXPECT_THROW(anywhere->read(special), FileRefused) << special;
  }
  EXPECT_THROW(anywhere->read((root_ / "fifo.xml").string()), FileRefused);
  EXPECT_FALSE(fifo_opened());
  EXPECT_EQ(anywhere->read((outside_ / "secret.xml").string()), "secret");
  // The watch does see an open (a non-blocking one, for the reader end).
  const int fd = ::open((root_ / "fifo.xml").c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(fd, 0);
  ::close(fd);
  EXPECT_TRUE(fifo_opened());
}

TEST_F(DataRootsTest, DotDotIsAppliedOnPaperSoNothingOutsideIsLookedAt) {
  // Through a folder outside, back into the root: the same answer whether that folder exists,
  // since it is never looked at (the kernel would resolve it, and fail where it is missing).
  write(outside_ / "existing" / "x", "");
  for (const fs::path& via :
       {outside_ / "existing", outside_ / "missing", base_ / "nowhere" / "deeper"}) {
    EXPECT_EQ(roots_->read((via / ".." / ".." / "root" / "inside.xml").string()), "<ENVIRONMENT/>")
        << via;
  }
  // Through a symbolic link inside the root, `..` does not follow the link: root/deep/.. is the
  // root, wherever deep points, and two levels up is outside.
  fs::create_directories(root_ / "a" / "b");
  fs::create_symlink(root_ / "a" / "b", root_ / "deep");
  EXPECT_EQ(roots_->read((root_ / "deep" / ".." / "inside.xml").string()), "<ENVIRONMENT/>");
  EXPECT_EQ(refusal((root_ / "deep" / ".." / ".." / "outside" / "secret.xml").string()),
            refusal((outside_ / "secret.xml").string()));
  EXPECT_EQ(roots_->identity((root_ / "deep" / ".." / "inside.xml").string()),
            (fs::canonical(root_) / "inside.xml").string());
}

/// Reads root/swap/f.xml over and over while another thread swaps the folder `swap` with a link
/// to outside/ (an atomic exchange of the two names); counts the reads of each content. 20,000
/// reads, or fewer once 4,000 of them met each way (inside and refused) 1,000 times: the reads
/// in the race, not the count, are what could lead outside.
struct SwapRace {
  int inside = 0, refused = 0, missing = 0, outside = 0;
};
SwapRace race_a_swapped_folder(const DataRoots& roots, const fs::path& root,
                               const fs::path& outside) {
  write(root / "swap" / "f.xml", "inside");
  write(outside / "f.xml", "OUTSIDE");
  fs::create_symlink(outside, root / "other");
  std::atomic<bool> done{false};
  std::thread swapper([&] {
    while (!done.load()) {
      ::renameat2(AT_FDCWD, (root / "swap").c_str(), AT_FDCWD, (root / "other").c_str(),
                  RENAME_EXCHANGE);
    }
  });
  SwapRace seen;
  const std::string path = (root / "swap" / "f.xml").string();
  for (int i = 0; i < 20000; ++i) {
    if (i >= 4000 && seen.inside >= 1000 && seen.refused >= 1000) break;
    try {
      const auto bytes = roots.read(path);
      if (!bytes) {
        ++seen.missing;
      } else if (*bytes == "inside") {
        ++seen.inside;
      } else {
        ++seen.outside;
      }
    } catch (const FileRefused&) {
      ++seen.refused;
    }
  }
  done.store(true);
  swapper.join();
  return seen;
}

TEST_F(DataRootsTest, AFolderSwappedForALinkDuringAReadNeverLeadsOutOfTheRoot) {
  for (const bool openat2 : {true, false}) {
    DataRoots::use_openat2(openat2);
    fs::remove_all(root_ / "swap");
    fs::remove_all(root_ / "other");
    const SwapRace seen = race_a_swapped_folder(*roots_, root_, outside_);
    // The race was run (both outcomes met) and never read what lies outside.
    EXPECT_EQ(seen.outside, 0) << (openat2 ? "openat2" : "one component at a time");
    EXPECT_GT(seen.inside, 0);
    EXPECT_GT(seen.refused, 0);
  }
  DataRoots::use_openat2(true);
  // Links and `..` that stay beneath the root still read, by either way.
  for (const bool openat2 : {true, false}) {
    DataRoots::use_openat2(openat2);
    EXPECT_EQ(roots_->read((root_ / "link_in.xml").string()), "<ENVIRONMENT/>");
    EXPECT_EQ(roots_->read((root_ / "sub" / ".." / "inside.xml").string()), "<ENVIRONMENT/>");
    EXPECT_EQ(roots_->read((root_ / "sub" / "deeper.xml").string()), "deeper");
  }
  DataRoots::use_openat2(true);
}

TEST_F(DataRootsTest, FilesOverTheSizeCapAreRefused) {
  write(root_ / "big.xml", std::string(2000, 'x'));
  const DataRoots small({root_.string()}, 1000);
  try {
    small.read((root_ / "big.xml").string());
    ADD_FAILURE() << "a file over the cap was read";
  } catch (const FileRefused& e) {
    EXPECT_NE(std::string(e.what()).find("larger than"), std::string::npos) << e.what();
  }
  EXPECT_EQ(small.read((root_ / "inside.xml").string()), "<ENVIRONMENT/>");
}

TEST_F(DataRootsTest, RootsMustBeFoldersOutsideTheKernelsFiles) {
  EXPECT_THROW(DataRoots({(root_ / "inside.xml").string()}), std::invalid_argument);
  EXPECT_THROW(DataRoots({(base_ / "nofolder").string()}), std::invalid_argument);
  for (const char* bad : {"/", "/proc", "/sys/kernel", "/dev"}) {
    EXPECT_THROW(DataRoots({bad}), std::invalid_argument) << bad;
  }
  const DataRoots twice({root_.string(), (root_ / ".." / "root").string()});
  EXPECT_EQ(twice.folders().size(), 1u);
}

TEST_F(DataRootsTest, TheLoaderAndTheWorldsOperationsAnswerWithTheRefusal) {
  write(root_ / "world.xml",
        "<WORLD><OBJECT><ID>box</ID><TYPE>PORTABLE</TYPE><SHAPE>BOX</SHAPE><DIMS>0.2,0.2,0.2</DIMS>"
        "<POS>0,0,0.1</POS></OBJECT></WORLD>");
  LoadOptions options;
  options.files = roots_.get();
  World world(load_world_file((root_ / "world.xml").string(), options));
  world.set_data_roots(roots_);
  const uint64_t hash = world.state_hash();
  const std::string secret = (outside_ / "secret.xml").string();
  EXPECT_THROW(load_world_file(secret, options), FileRefused);
  // An import or a texture named inside a world file fails at its line with the refusal.
  const std::string importing =
      "<WORLD><IMPORT><ID>s</ID><NAME>" + secret + "</NAME></IMPORT></WORLD>";
  try {
    load_world_string(importing, (root_ / "text.xml").string(), options);
    ADD_FAILURE() << "an import outside the roots was read";
  } catch (const WorldFileError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.message(), DataRoots::outside_message(secret));
  }
  const ObjectId box = world.objects().find_object("box").value();
  for (const std::string& path : {secret, (outside_ / "missing.bmp").string(),
                                  (root_ / "fifo.xml").string(), std::string("/dev/zero")}) {
    const Status texture = world.edit().set_texture(box, path);
    EXPECT_EQ(texture.code, ErrorCode::BadFile) << path << ": " << texture.message;
    const auto imported = world.edit().import_environment(path, "x", Pose{});
    EXPECT_EQ(imported.status.code, ErrorCode::BadFile) << path << ": " << imported.status.message;
    if (path.rfind(outside_.string(), 0) == 0) {
      EXPECT_EQ(texture.message, DataRoots::outside_message(path));
      EXPECT_EQ(imported.status.message, DataRoots::outside_message(path));
    }
  }
  EXPECT_FALSE(fifo_opened());
  EXPECT_EQ(world.state_hash(), hash);
  // Inside the roots the operations go on as before; a texture is kept as the file checked,
  // in one spelling (what the renderer reads later is what was checked).
  EXPECT_TRUE(world.edit().import_environment((root_ / "inside.xml").string(), "in", Pose{}).ok());
  ASSERT_TRUE(macsim::images::write_image((root_ / "tex.bmp").string(), cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3))));
  EXPECT_TRUE(world.edit().set_texture(box, (root_ / "sub" / ".." / "." / "tex.bmp").string()).ok());
  EXPECT_EQ(world.objects().object_texture(box).value.second, (fs::canonical(root_) / "tex.bmp").string());
}

}  // namespace
}  // namespace macsim
