#include "csv_writer.h"

#include <gtest/gtest.h>

#include <fstream>

#include "support/child_process.h"
#include "trial_record.h"

namespace affordances::csv {
namespace {

TEST(CsvWriter, QuotesAFieldOnlyWhenItHoldsACommaAQuoteOrALineEnd) {
  EXPECT_EQ(quote("plain"), "plain");
  EXPECT_EQ(quote(""), "");
  EXPECT_EQ(quote("0.125"), "0.125");
  EXPECT_EQ(quote("a,b"), "\"a,b\"");
  EXPECT_EQ(quote("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(quote("\""), "\"\"\"\"");
  EXPECT_EQ(quote("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(quote("cr\rhere"), "\"cr\rhere\"");
  EXPECT_EQ(quote("crlf\r\n"), "\"crlf\r\n\"");
  EXPECT_EQ(quote(" spaced "), " spaced ");  // spaces are part of a field, kept as they are
  EXPECT_EQ(join({"a", "b,c", "", "d\"e"}), "a,\"b,c\",,\"d\"\"e\"");
  EXPECT_EQ(join({}), "");
  EXPECT_EQ(join({""}), "");
}

TEST(CsvWriter, ReadsRfc4180Text) {
  const auto records = parse(
      "name,note\r\n"
      "plain,\"with, comma\"\n"
      "\n"
      "\"two\nlines\",\"\"\"quoted\"\"\"\n"
      "empty,\n"
      "\"\",last");
  ASSERT_EQ(records.size(), 5u);
  EXPECT_EQ(records[0].fields, (std::vector<std::string>{"name", "note"}));
  EXPECT_EQ(records[1].fields, (std::vector<std::string>{"plain", "with, comma"}));
  EXPECT_EQ(records[2].fields, (std::vector<std::string>{"two\nlines", "\"quoted\""}));
  EXPECT_EQ(records[3].fields, (std::vector<std::string>{"empty", ""}));
  EXPECT_EQ(records[4].fields, (std::vector<std::string>{"", "last"}));
  // Lines: the empty line 3 is skipped; the record on 4 spans two lines.
  EXPECT_EQ(records[1].line, 2);
  EXPECT_EQ(records[2].line, 4);
  EXPECT_EQ(records[3].line, 6);
  EXPECT_EQ(records[4].line, 7);
  for (std::size_t i = 0; i + 1 < records.size(); ++i) EXPECT_TRUE(records[i].ended) << i;
  EXPECT_FALSE(records[4].ended);  // no line end after it
  // Text that ends inside a quoted field: a record cut short.
  const auto cut = parse("a,b\n1,\"unfinished\n");
  ASSERT_EQ(cut.size(), 2u);
  EXPECT_FALSE(cut[1].ended);
  EXPECT_EQ(cut[1].fields, (std::vector<std::string>{"1", "unfinished\n"}));
  // Lenient where RFC 4180 is silent: stray quotes are characters of their field.
  EXPECT_EQ(split("a\"b,\"c\"d"), (std::vector<std::string>{"a\"b", "cd"}));
  EXPECT_TRUE(split("").empty());
  EXPECT_EQ(split(","), (std::vector<std::string>{"", ""}));
}

TEST(CsvWriter, WhatItWritesReadsBackTheSame) {
  const std::vector<std::vector<std::string>> rows{
      {"a", "b", "c", "d"},
      {"with, comma", "with \"quotes\"", "with\nnewline", "with\r\ncrlf"},
      {"", ",", "\"", "\"\""},
      {" lead", "trail ", "\",\n\"", "plain"}};
  std::string text;
  for (const auto& row : rows) text += join(row) + "\n";
  const auto records = parse(text);
  ASSERT_EQ(records.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(records[i].fields, rows[i]) << i;
    EXPECT_TRUE(records[i].ended);
    EXPECT_EQ(split(join(rows[i])), rows[i]) << i;
  }
}

struct Item {
  std::string name;
  int count = 0;
};

TEST(CsvWriter, HeaderAndRowsComeFromOneColumnList) {
  Columns<Item> columns;
  columns.add("name", [](const Item& i) { return i.name; })
      .add("count", [](const Item& i) { return std::to_string(i.count); })
      .add("odd, name", [](const Item& i) { return i.count % 2 ? "yes" : "no"; });
  EXPECT_EQ(columns.size(), 3u);
  EXPECT_EQ(columns.header(), "name,count,\"odd, name\"");
  EXPECT_EQ(columns.row(Item{"a \"box\", red", 3}), "\"a \"\"box\"\", red\",3,yes");
  EXPECT_EQ(columns.fields(Item{"x", 2}), (std::vector<std::string>{"x", "2", "no"}));
  const auto records = parse(columns.header() + "\n" + columns.row(Item{"a,b", 1}) + "\n");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].fields, columns.names());
  EXPECT_EQ(records[1].fields, (std::vector<std::string>{"a,b", "1", "yes"}));
}

// The trial rows go through the writer: a material name with a comma, a quote and a line end
// (no material has one, but nothing in the file format forbids it) comes back as it was, and
// the row keeps as many fields as the header.
TEST(CsvWriter, TrialRowsWithAwkwardFieldsReadBack) {
  TrialRecord r;
  r.spec = make_trial(Affordance::Lift, Generator::Material, 5);
  r.spec.material = "steel, \"painted\"\nred";
  r.outcome.label = "liftable";
  macsim::test::TempDir dir("csv_writer_");
  const std::string path = dir.path() + "/rows.csv";
  std::ofstream(path) << csv_header() << "\n" << csv_row(r) << "\n" << csv_row(r) << "\n";
  const CsvTable t = read_csv(path);
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.columns, split(csv_header()));
  EXPECT_EQ(t.rows[0], csv_fields(r));
  EXPECT_EQ(t.rows[1][*t.column("material")], r.spec.material);
  EXPECT_EQ(t.rows[1][*t.column("label")], "liftable");
  // Cut inside the quoted field: the last row is dropped, not an error.
  const std::string row = csv_row(r);
  std::ofstream(path) << csv_header() << "\n" << row << "\n" << row.substr(0, row.find('\n'));
  EXPECT_EQ(read_csv(path).rows.size(), 1u);
}

}  // namespace
}  // namespace affordances::csv
