// What the picture server lets requests make it keep: pictures waiting to be taken or rendered
// (each holds a captured scene) and distinct files written into the pictures folder in one run.
#pragma once

#include <cstddef>
#include <optional>
#include <set>
#include <string>

namespace macsim {

/// Admits picture requests within a cap on those in flight and on distinct file names.
class PictureAdmission {
 public:
  PictureAdmission(std::size_t max_in_flight, std::size_t max_files)
      : max_in_flight_(max_in_flight), max_files_(max_files) {}

  /// Takes the request named `name` in (nullopt), or says why not (the reply's message).
  std::optional<std::string> admit(const std::string& name) {
    if (in_flight_ >= max_in_flight_) {
      return "busy: " + std::to_string(in_flight_) +
             " pictures are being taken or rendered, the cap on waiting pictures (" +
             std::to_string(max_in_flight_) + "); ask again once one is answered";
    }
    if (!files_.count(name) && files_.size() >= max_files_) {
      return "'" + name + "' would be a new file: " + std::to_string(files_.size()) +
             " distinct picture files were written in this run, the cap (" +
             std::to_string(max_files_) +
             ", macsim --max-pictures); write over a name used before, or raise the cap";
    }
    files_.insert(name);
    ++in_flight_;
    return std::nullopt;
  }
  /// An admitted request was answered (its name stays counted, written or not).
  void done() {
    if (in_flight_ > 0) --in_flight_;
  }
  std::size_t in_flight() const { return in_flight_; }
  std::size_t files() const { return files_.size(); }

 private:
  std::size_t max_in_flight_;
  std::size_t max_files_;
  std::size_t in_flight_ = 0;
  std::set<std::string> files_;  // names admitted in this run
};

}  // namespace macsim
