#include "csv_writer.h"

namespace affordances::csv {

std::string quote(std::string_view field) {
  if (field.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(field);
  std::string out;
  out.reserve(field.size() + 2);
  out += '"';
  for (char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
  return out;
}

std::string join(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i) line += ',';
    line += quote(fields[i]);
  }
  return line;
}

std::vector<ReadRecord> parse(std::string_view text) {
  std::vector<ReadRecord> records;
  ReadRecord record;
  std::string field;
  int line = 1;
  std::size_t i = 0;
  const std::size_t n = text.size();
  // A line end at i (LF or CRLF): its length, 0 when there is none.
  auto line_end = [&](std::size_t at) -> std::size_t {
    if (at < n && text[at] == '\n') return 1;
    if (at + 1 < n && text[at] == '\r' && text[at + 1] == '\n') return 2;
    return 0;
  };
  while (i < n) {
    // At the start of a record: skip empty lines.
    if (const std::size_t end = line_end(i)) {
      i += end;
      ++line;
      continue;
    }
    record = ReadRecord{{}, line, false};
    // The fields of one record.
    while (true) {
      field.clear();
      bool closed = true;  // an unquoted field, or a quoted one whose closing quote was read
      if (i < n && text[i] == '"') {
        closed = false;
        ++i;
        while (i < n) {
          if (text[i] == '"') {
            if (i + 1 < n && text[i + 1] == '"') {
              field += '"';
              i += 2;
              continue;
            }
            ++i;
            closed = true;
            break;
          }
          if (text[i] == '\n') ++line;
          field += text[i++];
        }
      }
      // Unquoted characters (or what follows a closing quote) up to a comma or a line end.
      while (closed && i < n && text[i] != ',' && line_end(i) == 0) field += text[i++];
      record.fields.push_back(field);
      if (!closed || i >= n) break;  // the text ended within the record
      if (text[i] == ',') {
        ++i;
        continue;
      }
      i += line_end(i);
      ++line;
      record.ended = true;
      break;
    }
    records.push_back(std::move(record));
  }
  return records;
}

std::vector<std::string> split(std::string_view line) {
  auto records = parse(line);
  if (records.empty()) return {};
  return std::move(records.front().fields);
}

}  // namespace affordances::csv
