#include "dem/io/csv_table.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/input_error.h"

namespace trackbed::dem {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// Splits on every comma, so "1,2,3," has four fields and the count check catches it.
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

}  // namespace

CsvTable::CsvTable(const std::string& path, const std::string& what) : path_(path) {
  std::ifstream in(path);
  if (!in)
    throw InputError(path + ": cannot open " + what + "; valid: an existing, readable CSV file");
  std::string line;
  int lineno = 0;
  bool have_header = false;
  std::size_t nfields = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    auto fields = split(t);
    if (!have_header) {
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].empty())
          throw input_error_at(path, lineno, "empty column name in the header");
        if (!columns_.emplace(fields[i], static_cast<int>(i)).second)
          throw input_error_at(path, lineno,
                               "column '" + fields[i] + "' appears twice in the header");
      }
      nfields = fields.size();
      have_header = true;
      header_line_ = lineno;
      continue;
    }
    if (fields.size() != nfields)
      throw input_error_at(path, lineno,
                           "row has " + std::to_string(fields.size()) +
                               " fields but the header (line " + std::to_string(header_line_) +
                               ") has " + std::to_string(nfields) +
                               "; give one value per header column");
    rows_.push_back(std::move(fields));
    lines_.push_back(lineno);
  }
  if (!have_header)
    throw input_error_at(path, std::max(lineno, 1),
                         what + " has no header line; valid: a first line naming the columns");
}

void CsvTable::require(const std::string& column) const {
  if (has(column)) return;
  std::string names;
  for (const auto& [name, i] : columns_) names += (names.empty() ? "" : ", ") + name;
  throw input_error_at(path_, header_line_,
                       "header has no column '" + column + "'; it has: " + names);
}

const std::string& CsvTable::text(int row, const std::string& column) const {
  require(column);
  return rows_[row][columns_.at(column)];
}

double CsvTable::number(int row, const std::string& column) const {
  const std::string& s = text(row, column);
  double v = 0;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, v);
  if (s.empty() || ec != std::errc() || ptr != end || !std::isfinite(v))
    throw input_error_at(
        path_, lines_[row],
        "column '" + column + "': '" + s + "' is not valid; it must be a finite number");
  return v;
}

double CsvTable::number_or(int row, const std::string& column, double fallback) const {
  if (!has(column) || text(row, column).empty()) return fallback;
  return number(row, column);
}

}  // namespace trackbed::dem
