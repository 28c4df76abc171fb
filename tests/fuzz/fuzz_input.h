// How the fuzzers cut their input into parts: a bundle of files for the world loader, and a
// sequence of length-prefixed records for the request targets.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace macsim::fuzz {

/// Separates the files of a bundle: the root world first, then "\n\x01FILE name\n" + bytes for
/// each other file, its name relative to the root's directory.
inline constexpr std::string_view kFileMark =
    "\n\x01"
    "FILE ";

/// The files of a bundle as (name, bytes); the first is named "world.xml".
inline std::vector<std::pair<std::string, std::string>> split_bundle(std::string_view input) {
  std::vector<std::pair<std::string, std::string>> files;
  std::string name = "world.xml";
  for (;;) {
    const std::size_t mark = input.find(kFileMark);
    files.emplace_back(name, std::string(input.substr(0, mark)));
    if (mark == std::string_view::npos) return files;
    input.remove_prefix(mark + kFileMark.size());
    const std::size_t end = input.find('\n');
    name = std::string(input.substr(0, end));
    if (end == std::string_view::npos) return files;
    input.remove_prefix(end + 1);
  }
}

/// One record of a request sequence: a kind byte, a two-byte little-endian length, the bytes.
struct Record {
  uint8_t kind;
  std::string_view bytes;
};

/// The records of `input`; a truncated last record is cut to what is there.
inline std::vector<Record> split_records(std::string_view input) {
  std::vector<Record> records;
  while (input.size() >= 3) {
    const uint8_t kind = uint8_t(input[0]);
    const std::size_t length = uint8_t(input[1]) | (std::size_t(uint8_t(input[2])) << 8);
    input.remove_prefix(3);
    const std::size_t n = std::min(length, input.size());
    records.push_back({kind, input.substr(0, n)});
    input.remove_prefix(n);
  }
  return records;
}

/// A record as split_records reads it back.
inline std::string record(uint8_t kind, const std::string& bytes) {
  std::string out(3, '\0');
  out[0] = char(kind);
  out[1] = char(bytes.size() & 0xff);
  out[2] = char((bytes.size() >> 8) & 0xff);
  return out + bytes;
}

}  // namespace macsim::fuzz
