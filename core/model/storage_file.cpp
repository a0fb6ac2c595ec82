// SPDX-License-Identifier: Apache-2.0
#include "model/storage_file.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "io/file_checks.h"
#include "io/text.h"

namespace rbfmuscle {
namespace {

using io::trimWhitespace;

/// `"text"` → `text`; anything else as it is.
std::string unquote(const std::string& s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return trimWhitespace(s.substr(1, s.size() - 2));
  return s;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  std::ostringstream m;
  m << "storage file " << path;
  if (line > 0) m << ", line " << line;
  m << ": " << what;
  throw ModelError(m.str());
}

/// Splits a label row on tabs (labels may contain spaces), or on any white
/// space when the row has no tab.
std::vector<std::string> splitLabels(const std::string& line) {
  if (line.find('\t') == std::string::npos) return io::splitWords(line);
  std::vector<std::string> labels = io::splitTrimmed(line, '\t');
  labels.erase(std::remove(labels.begin(), labels.end(), std::string()), labels.end());
  return labels;
}

/// Parses a non-negative integer header value such as `nRows=12`.
long parseCount(const std::string& path, int line, const std::string& key,
                const std::string& value) {
  char* end = nullptr;
  errno = 0;
  const long n = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || errno != 0 || n < 0)
    fail(path, line, "header '" + key + "=" + value + "': expected a non-negative integer");
  return n;
}

/// Formats with max_digits10 significant digits so that write→read is exact.
std::string formatNumber(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", std::numeric_limits<double>::max_digits10, v);
  return buf;
}

void checkTable(const std::string& path, const StorageTable& table) {
  if (table.column_labels.empty()) fail(path, 0, "cannot write a table without column labels");
  for (const auto& label : table.column_labels)
    if (label.empty() || label.find_first_of("\t\r\n") != std::string::npos)
      fail(path, 0, "cannot write column label '" + label +
                        "': labels must be non-empty and contain no tab or line break");
  if (table.name.find_first_of("\r\n") != std::string::npos)
    fail(path, 0, "cannot write table name '" + table.name + "': it contains a line break");
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    if (table.rows[r].size() != table.column_labels.size())
      fail(path, 0, "cannot write row " + std::to_string(r) + ": it has " +
                        std::to_string(table.rows[r].size()) + " values, expected " +
                        std::to_string(table.column_labels.size()) + " (one per column label)");
}

/// Writes `text` to a temporary file beside `path`, then renames it over `path`.
void writeAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp" + std::to_string(static_cast<long>(::getpid()));
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) fail(path, 0, "cannot open temporary file " + tmp + " for writing: " + std::strerror(errno));
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) {
    std::remove(tmp.c_str());
    fail(path, 0, "cannot write temporary file " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    fail(path, 0, "cannot rename " + tmp + " to it: " + why);
  }
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

StorageTable readStorageStream(std::istream& in, const std::string& path);

}  // namespace

int StorageTable::findColumn(const std::string& label) const {
  for (std::size_t i = 0; i < column_labels.size(); ++i)
    if (column_labels[i] == label) return static_cast<int>(i);
  return -1;
}

StorageTable readStorage(const std::string& path) {
  {
    const std::string problem = io::findInputFileProblem(path, "a storage file (.sto/.mot)");
    if (!problem.empty()) fail(path, 0, problem.rfind("is ", 0) == 0 ? "it " + problem : problem);
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && bytes > kMaxStorageFileBytes)
      fail(path, 0, std::to_string(bytes) + " bytes, more than the " + std::to_string(kMaxStorageFileBytes) +
                        " a storage file may have");
  }
  std::ifstream in(path);
  if (!in) fail(path, 0, "cannot open it for reading (missing or unreadable)");
  return readStorageStream(in, path);
}

StorageTable parseStorageText(const std::string& text, const std::string& path) {
  if (text.size() > kMaxStorageFileBytes)
    fail(path, 0, std::to_string(text.size()) + " bytes, more than the " + std::to_string(kMaxStorageFileBytes) +
                      " a storage file may have");
  std::istringstream in(text);
  return readStorageStream(in, path);
}

namespace {

/// A storage stream read line by line: the current line and its number (1-based), for errors.
struct LineCursor {
  LineCursor(std::istream& stream, const std::string& file_path) : in(stream), path(file_path) {}

  std::istream& in;
  const std::string& path;
  std::string line;
  int line_no = 0;

  /// Reads the next line into `line`; false at the end of the stream.
  bool next() {
    if (!std::getline(in, line)) return false;
    ++line_no;
    return true;
  }
};

/// The row and column counts a header declares (-1: not declared) and the lines declaring them.
struct HeaderCounts {
  long rows = -1, columns = -1;
  int rows_line = 0, columns_line = 0;
};

/// One `key=value` header line (keys and values may be quoted); unknown keys are ignored.
void readHeaderSetting(const LineCursor& cursor, const std::string& line, std::size_t eq, HeaderCounts& counts,
                       StorageTable& table) {
  const std::string& path = cursor.path;
  const int line_no = cursor.line_no;
  const std::string key = unquote(trimWhitespace(line.substr(0, eq)));
  const std::string value = unquote(trimWhitespace(line.substr(eq + 1)));
  if (key == "inDegrees") {
    const std::string v = lower(value);
    if (v == "yes" || v == "true") table.in_degrees = true;
    else if (v == "no" || v == "false") table.in_degrees = false;
    else fail(path, line_no, "header 'inDegrees=" + value + "': expected yes or no");
  } else if (key == "nRows") {
    counts.rows = parseCount(path, line_no, key, value);
    counts.rows_line = line_no;
  } else if (key == "nColumns") {
    counts.columns = parseCount(path, line_no, key, value);
    counts.columns_line = line_no;
  }
}

/// Header: an optional name line, then key=value lines (OpenSim; keys and values may be
/// quoted), or `datarows N` / `datacolumns N` (SIMM motion files), up to `endheader`.
HeaderCounts readHeader(LineCursor& cursor, StorageTable& table) {
  HeaderCounts counts;
  bool have_end = false;
  while (cursor.next()) {
    const std::string t = trimWhitespace(cursor.line);
    if (t == "endheader") {
      have_end = true;
      break;
    }
    const auto eq = t.find('=');
    if (eq != std::string::npos) {
      readHeaderSetting(cursor, t, eq, counts, table);
      continue;
    }
    std::istringstream words(t);
    std::string word, count, extra;
    words >> word >> count;
    if ((word == "datarows" || word == "datacolumns") && !count.empty() && !(words >> extra)) {
      const long n = parseCount(cursor.path, cursor.line_no, word, count);
      (word == "datarows" ? counts.rows : counts.columns) = n;
      (word == "datarows" ? counts.rows_line : counts.columns_line) = cursor.line_no;
    } else if (cursor.line_no == 1) {
      table.name = t;
    }
    // free-text header lines ("Units are S.I. units ...") are allowed
  }
  if (!have_end) fail(cursor.path, cursor.line_no, "no 'endheader' line before the end of the file");
  return counts;
}

/// Column labels: the first non-blank line after `endheader`, starting with `time`, each once.
void readColumnLabels(LineCursor& cursor, const HeaderCounts& counts, StorageTable& table) {
  const std::string& path = cursor.path;
  while (cursor.next())
    if (!trimWhitespace(cursor.line).empty()) break;
  table.column_labels = splitLabels(cursor.line);
  if (table.column_labels.empty())
    fail(path, cursor.line_no, "no row of column labels after 'endheader'");
  const int labels_line = cursor.line_no;
  if (table.column_labels[0] != "time")
    fail(path, labels_line,
         "first column label is '" + table.column_labels[0] + "', expected 'time'");
  std::set<std::string> seen;
  for (const auto& label : table.column_labels)
    if (!seen.insert(label).second)
      fail(path, labels_line, "column label '" + label + "' appears twice");
  if (counts.columns >= 0 && static_cast<std::size_t>(counts.columns) != table.column_labels.size())
    fail(path, counts.columns_line,
         "header says nColumns=" + std::to_string(counts.columns) + " but the label row (line " +
             std::to_string(labels_line) + ") has " +
             std::to_string(table.column_labels.size()) + " labels");
}

/// Data rows: white-space separated numbers, one per column.
void readDataRows(LineCursor& cursor, StorageTable& table) {
  const std::size_t width = table.column_labels.size();
  while (cursor.next()) {
    if (trimWhitespace(cursor.line).empty()) continue;
    std::istringstream ss(cursor.line);
    std::vector<double> row;
    row.reserve(width);
    std::string token;
    while (ss >> token) {
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0')
        fail(cursor.path, cursor.line_no,
             "value '" + token + "' in column " + std::to_string(row.size() + 1) +
                 (row.size() < width ? " ('" + table.column_labels[row.size()] + "')" : "") +
                 " is not a number");
      row.push_back(v);
    }
    if (row.size() != width)
      fail(cursor.path, cursor.line_no,
           "row has " + std::to_string(row.size()) + " values, expected " +
               std::to_string(width) + " (one per column label)");
    table.rows.push_back(std::move(row));
    table.row_lines.push_back(cursor.line_no);
  }
}

StorageTable readStorageStream(std::istream& in, const std::string& path) {
  StorageTable table;
  LineCursor cursor(in, path);
  const HeaderCounts counts = readHeader(cursor, table);
  readColumnLabels(cursor, counts, table);
  readDataRows(cursor, table);
  if (counts.rows >= 0 && static_cast<std::size_t>(counts.rows) != table.rows.size())
    fail(path, counts.rows_line,
         "header says nRows=" + std::to_string(counts.rows) + " but the file has " +
             std::to_string(table.rows.size()) + " data rows");
  return table;
}

}  // namespace

void writeStorage(const std::string& path, const StorageTable& table) {
  checkTable(path, table);
  std::string out;
  out += (table.name.empty() ? std::string("storage") : table.name) + "\n";
  out += "version=1\n";
  out += "nRows=" + std::to_string(table.rows.size()) + "\n";
  out += "nColumns=" + std::to_string(table.column_labels.size()) + "\n";
  out += std::string("inDegrees=") + (table.in_degrees ? "yes" : "no") + "\n";
  out += "endheader\n";
  for (std::size_t c = 0; c < table.column_labels.size(); ++c)
    out += (c ? "\t" : "") + table.column_labels[c];
  out += "\n";
  for (const auto& row : table.rows) {
    for (std::size_t c = 0; c < row.size(); ++c) out += (c ? "\t" : "") + formatNumber(row[c]);
    out += "\n";
  }
  writeAtomically(path, out);
}

void writeCsv(const std::string& path, const StorageTable& table) {
  checkTable(path, table);
  std::string out;
  for (std::size_t c = 0; c < table.column_labels.size(); ++c)
    out += (c ? "," : "") + csvField(table.column_labels[c]);
  out += "\n";
  for (const auto& row : table.rows) {
    for (std::size_t c = 0; c < row.size(); ++c) out += (c ? "," : "") + formatNumber(row[c]);
    out += "\n";
  }
  writeAtomically(path, out);
}

}  // namespace rbfmuscle
