// A small reader of the CSV files users give (particles, templates, sieve tables): a header line
// naming the columns, then rows; '#' comment lines and blank lines are skipped. Every error names
// the file and line, as a compiler does.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace trackbed::dem {

class CsvTable {
 public:
  // Reads the whole file; throws InputError if it is missing, has no header, or a row has a
  // different number of fields than the header.
  // `what` names the contents in messages ("clump template 'stone'", "particle file").
  explicit CsvTable(const std::string& path, const std::string& what = "CSV file");

  const std::string& path() const { return path_; }
  int num_rows() const { return static_cast<int>(rows_.size()); }
  int line_of(int row) const { return lines_[row]; }
  int header_line() const { return header_line_; }
  bool has(const std::string& column) const { return columns_.count(column) > 0; }
  // Throws InputError naming the file and the columns it has when `column` is missing.
  void require(const std::string& column) const;

  const std::string& text(int row, const std::string& column) const;
  // A finite number (read with from_chars: the C locale does not matter); throws InputError at
  // the row's line otherwise.
  double number(int row, const std::string& column) const;
  // The number if the column exists and the field is not empty, else `fallback`.
  double number_or(int row, const std::string& column, double fallback) const;

 private:
  std::string path_;
  std::map<std::string, int> columns_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<int> lines_;
  int header_line_ = 0;
};

}  // namespace trackbed::dem
