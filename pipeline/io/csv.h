// Comma-separated tables as kurage writes them (study.csv, bodies.csv, sim_frames.csv): a header
// line of column names, then one record per line, fields quoted as RFC 4180 does where they hold
// a comma, a quote or a line break (a line break is written as a space). Numbers are written by
// the caller; an empty field is a value that was not there (read back as NaN).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace kurage::pipeline {

// A field, quoted where it must be.
std::string csvField(const std::string& text);
// The fields of one line (quotes as csvField writes them).
std::vector<std::string> csvRecord(const std::string& line);

// A whole table, every record the header's width. Messages name `file`.
struct CsvTable {
  std::string file;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  std::optional<size_t> column(const std::string& name) const;
  bool has(const std::string& name) const { return column(name).has_value(); }
  // The column's values as numbers (an empty field: NaN). Throws std::runtime_error naming the
  // file, line and column for a missing column or a field that is not a number.
  std::vector<double> numbers(const std::string& name) const;
};

// Parses `text`. Throws std::runtime_error naming `file` for an empty text or a record whose
// width differs from the header's (with its line number).
CsvTable parseCsvTable(const std::string& text, const std::string& file);

}  // namespace kurage::pipeline
