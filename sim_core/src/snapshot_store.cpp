#include "macsim/sim_core/snapshot_store.h"

namespace macsim {

namespace {

const char* const kHowToMakeRoom =
    "; delete a snapshot, save under a name already kept to replace it, or raise the cap";

}  // namespace

std::size_t SnapshotStore::footprint(const std::string& name, const WorldSnapshot& snapshot) {
  using Node = std::map<std::string, WorldSnapshot>::value_type;
  // A map node: the pair, three links and a colour; the name beyond the string's own buffer.
  return sizeof(Node) + 4 * sizeof(void*) + name.size() + snapshot.bytes.capacity();
}

Status SnapshotStore::save(const std::string& name, WorldSnapshot snapshot) {
  snapshot.bytes.shrink_to_fit();  // what is counted is what is kept
  const std::size_t size = footprint(name, snapshot);
  const auto found = snapshots_.find(name);
  const std::size_t freed = found == snapshots_.end() ? 0 : footprint(found->first, found->second);
  if (found == snapshots_.end() && snapshots_.size() >= limits_.max_count) {
    return Status::error(ErrorCode::LimitReached,
                         "cannot keep snapshot '" + name + "': " +
                             std::to_string(snapshots_.size()) +
                             " named snapshots are kept, the cap on their count (" +
                             std::to_string(limits_.max_count) + ", macsim --max-snapshots)" +
                             kHowToMakeRoom);
  }
  if (bytes_ - freed + size > limits_.max_bytes) {
    return Status::error(
        ErrorCode::LimitReached,
        "cannot keep snapshot '" + name + "' of " + std::to_string(size) + " bytes: the " +
            std::to_string(snapshots_.size()) + " snapshots kept take " + std::to_string(bytes_) +
            " bytes" + (freed ? " (" + std::to_string(freed) + " of them the one it replaces)" : "") +
            ", the cap on their bytes is " + std::to_string(limits_.max_bytes) +
            " (macsim --max-snapshot-bytes)" + kHowToMakeRoom);
  }
  if (found != snapshots_.end()) {
    bytes_ -= freed;
    found->second = std::move(snapshot);
  } else {
    snapshots_.emplace(name, std::move(snapshot));
  }
  bytes_ += size;
  return Status{};
}

const WorldSnapshot* SnapshotStore::find(const std::string& name) const {
  const auto found = snapshots_.find(name);
  return found == snapshots_.end() ? nullptr : &found->second;
}

Status SnapshotStore::remove(const std::string& name) {
  const auto found = snapshots_.find(name);
  if (found == snapshots_.end()) {
    return Status::error(ErrorCode::InvalidArgument,
                         "no snapshot named '" + name + "' of this world");
  }
  bytes_ -= footprint(found->first, found->second);
  snapshots_.erase(found);
  return Status{};
}

std::vector<std::string> SnapshotStore::names() const {
  std::vector<std::string> names;
  names.reserve(snapshots_.size());
  for (const auto& [name, snapshot] : snapshots_) names.push_back(name);
  return names;
}

void SnapshotStore::clear() {
  snapshots_.clear();
  bytes_ = 0;
}

}  // namespace macsim
