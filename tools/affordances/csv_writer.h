// CSV as RFC 4180 has it, written from one list of columns and read back.
//
// A table's columns are one list: each a name and how a record gives its field. The header
// and every row are written from that list, so they cannot drift apart. A field holding a
// comma, a double quote, CR or LF is quoted and its quotes doubled; any other is written as it
// is. The reader takes what the writer writes (and any RFC 4180 text): quoted fields, line ends
// within them, LF or CRLF line ends.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace affordances::csv {

/// `field` as a CSV field: in double quotes, its quotes doubled, when it holds a comma, a double
/// quote, CR or LF; as it is otherwise.
std::string quote(std::string_view field);

/// The fields as one CSV line (no line end), each quoted as it needs.
std::string join(const std::vector<std::string>& fields);

/// One record read back: its fields as written (unquoted), the line it begins on (1 for the
/// first), and whether its line end was there (false: the text ended within it, as a file does
/// whose writer was killed mid-row).
struct ReadRecord {
  std::vector<std::string> fields;
  int line = 0;
  bool ended = true;
};

/// Every record of `text`, in order; empty lines are skipped. A quoted field may hold commas,
/// quotes (doubled) and line ends; a quote within an unquoted field, or after a quoted field's
/// closing quote, is taken as a character of the field.
std::vector<ReadRecord> parse(std::string_view text);

/// The fields of one line as join() writes it (the whole of `line` is one record).
std::vector<std::string> split(std::string_view line);

/// The columns of a table of `Record`s: each a name and how a record gives its field. The header
/// and the rows come from the same list.
template <class Record>
class Columns {
 public:
  using Field = std::function<std::string(const Record&)>;

  /// Appends a column; returns *this, to chain.
  Columns& add(std::string name, Field field) {
    names_.push_back(std::move(name));
    fields_.push_back(std::move(field));
    return *this;
  }

  const std::vector<std::string>& names() const { return names_; }
  std::size_t size() const { return names_.size(); }

  /// The header line (no line end).
  std::string header() const { return join(names_); }

  /// A record's fields, one per column, unquoted.
  std::vector<std::string> fields(const Record& record) const {
    std::vector<std::string> out;
    out.reserve(fields_.size());
    for (const auto& field : fields_) out.push_back(field(record));
    return out;
  }

  /// A record's row (no line end).
  std::string row(const Record& record) const { return join(fields(record)); }

 private:
  std::vector<std::string> names_;
  std::vector<Field> fields_;
};

}  // namespace affordances::csv
