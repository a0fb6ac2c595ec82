// SPDX-License-Identifier: Apache-2.0
#include "fit/rbf_file.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "io/file_checks.h"

namespace rbfmuscle {
namespace {

/// Line-by-line reader that skips comments and names file:line in errors.
class RecordReader {
 public:
  /// Reads `in`, which holds `file_bytes` bytes; `path` names the file in errors.
  RecordReader(std::istream& in, std::uintmax_t file_bytes, const std::string& path)
      : path_(path), in_(in), file_bytes_(file_bytes) {}

  std::uintmax_t getFileBytes() const { return file_bytes_; }
  int getLineNumber() const { return line_number_; }

  /// Fails at the first non-comment line left in the file (records beyond the declared count).
  void expectEnd(const std::string& what) {
    std::string line;
    if (nextRecord(line)) fail(what);
  }

  /// Next non-comment line split at its first space into key and rest.
  void next(const std::string& expected_key, std::string& rest) {
    std::string line;
    if (!nextRecord(line)) fail("file ends before '" + expected_key + "'");
    const std::size_t space = line.find(' ');
    const std::string key = line.substr(0, space);
    if (key != expected_key) fail("expected '" + expected_key + "', found '" + key + "'");
    rest = space == std::string::npos ? "" : line.substr(space + 1);
  }

  /// Next non-comment line as `count` numbers.
  void nextNumbers(int count, double* values) {
    std::string line;
    if (!nextRecord(line)) fail("file ends early: expected " + std::to_string(count) + " numbers");
    parseNumbers(line, count, values);
  }

  void parseNumbers(const std::string& text, int count, double* values) const {
    std::istringstream fields(text);
    for (int k = 0; k < count; ++k) {
      std::string token;
      if (!(fields >> token)) fail("expected " + std::to_string(count) + " numbers, got " + std::to_string(k));
      char* end = nullptr;
      values[k] = std::strtod(token.c_str(), &end);
      if (*end != '\0' || !std::isfinite(values[k])) fail("'" + token + "' is not a finite number");
    }
    std::string extra;
    if (fields >> extra) fail("unexpected '" + extra + "' after " + std::to_string(count) + " numbers");
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw RbfFileError(path_ + ":" + std::to_string(line_number_) + ": " + what);
  }

 private:
  /// Next line that is neither empty nor a comment, without the CR a file with Windows line
  /// ends has before each LF; false at the end of the file.
  bool nextRecord(std::string& line) {
    while (std::getline(in_, line)) {
      ++line_number_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!line.empty() && line[0] != '#') return true;
    }
    return false;
  }

  std::string path_;
  std::istream& in_;
  int line_number_ = 0;
  std::uintmax_t file_bytes_ = 0;
};

/// Fails through `reader` when |value| exceeds `bound`, naming `what`.
void checkMagnitude(const RecordReader& reader, double value, double bound, const std::string& what) {
  if (std::abs(value) > bound) {
    std::ostringstream text;
    text << what << " " << value << " has a magnitude above " << bound << " (see rbf_file.h)";
    reader.fail(text.str());
  }
}

RbfSurface readRbf(std::istream& in, std::uintmax_t file_bytes, const std::string& path);

}  // namespace

void writeRbfFile(const std::string& path, const RbfSurface& s) {
  const std::string temporary = path + ".partial";
  {
    std::ofstream out(temporary);
    if (!out) throw RbfFileError(path + ": cannot write (check the directory exists and is writable)");
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    out << "# rbfmuscle Gaussian RBF surface: f(x) = offset + sum_k weight_k exp(-shape_k |x - centre_k|^2)\n"
        << "rbfmuscle_rbf " << kRbfFileVersion << "\n"
        << "units mm\n"
        << "source_mesh " << s.source_mesh << "\n"
        << "source_hash " << s.source_hash << "\n"
        << "frame_offset_mm " << s.frame_offset_mm.x() << ' ' << s.frame_offset_mm.y() << ' '
        << s.frame_offset_mm.z() << "\n"
        << "offset " << s.field.getOffset() << "\n"
        << "cutoff " << s.field.getCutoff() << "\n"
        << "settings " << s.settings << "\n"
        << "metrics " << s.metrics_json << "\n"
        << "centres " << s.field.getNumCentres() << "\n"
        << "# x_mm y_mm z_mm weight_mm shape_per_mm2\n";
    const Eigen::Matrix3Xd& c = s.field.getCentres();
    for (int k = 0; k < s.field.getNumCentres(); ++k)
      out << c(0, k) << ' ' << c(1, k) << ' ' << c(2, k) << ' ' << s.field.getWeights()[k] << ' '
          << s.field.getShapes()[k] << '\n';
    out.flush();
    if (!out) {
      std::remove(temporary.c_str());
      throw RbfFileError(path + ": write failed");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw RbfFileError(path + ": cannot move the finished file into place");
  }
}

RbfSurface readRbfFile(const std::string& path) {
  const std::string problem = io::findInputFileProblem(path, "a .rbf surface file");
  if (problem.rfind("is ", 0) == 0) throw RbfFileError(path + ": cannot open the .rbf file: it " + problem);
  if (!problem.empty()) throw RbfFileError(path + ": cannot open the .rbf file (missing or unreadable)");
  std::ifstream in(path);
  if (!in) throw RbfFileError(path + ": cannot open the .rbf file");
  std::error_code ec;
  const std::uintmax_t file_bytes = std::filesystem::file_size(path, ec);
  return readRbf(in, file_bytes, path);
}

RbfSurface parseRbfText(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  return readRbf(in, text.size(), path);
}

namespace {

RbfSurface readRbf(std::istream& in, std::uintmax_t file_bytes, const std::string& path) {
  RecordReader reader(in, file_bytes, path);
  RbfSurface s;
  std::string rest;
  reader.next("rbfmuscle_rbf", rest);
  if (rest != std::to_string(kRbfFileVersion))
    reader.fail("unsupported version '" + rest + "' (this build reads version " +
                std::to_string(kRbfFileVersion) + ")");
  reader.next("units", rest);
  if (rest != "mm") reader.fail("units must be 'mm', found '" + rest + "'");
  reader.next("source_mesh", s.source_mesh);
  reader.next("source_hash", s.source_hash);
  reader.next("frame_offset_mm", rest);
  reader.parseNumbers(rest, 3, s.frame_offset_mm.data());
  for (int k = 0; k < 3; ++k) checkMagnitude(reader, s.frame_offset_mm[k], kMaxRbfCoordinateMm, "frame offset");
  double offset = 0.0, cutoff = 0.0, count = 0.0;
  reader.next("offset", rest);
  reader.parseNumbers(rest, 1, &offset);
  checkMagnitude(reader, offset, kMaxRbfWeight, "offset");
  reader.next("cutoff", rest);
  reader.parseNumbers(rest, 1, &cutoff);
  if (!(cutoff >= 0 && cutoff < 1)) reader.fail("cutoff must be in [0, 1)");
  reader.next("settings", s.settings);
  reader.next("metrics", s.metrics_json);
  reader.next("centres", rest);
  reader.parseNumbers(rest, 1, &count);
  if (count < 1 || count != std::floor(count) || count > kMaxRbfCentres)
    reader.fail("centre count must be a whole number from 1 to " + std::to_string(kMaxRbfCentres) + ", got '" +
                rest + "'" + (count == 0 ? " (a surface needs at least one centre)" : ""));
  const int n = static_cast<int>(count);
  const int count_line = reader.getLineNumber();
  // Each centre line holds five numbers: at least "0 0 0 0 1\n", 10 bytes.
  if (!io::countFitsInBytes(n, 10, reader.getFileBytes()))
    reader.fail("declares " + std::to_string(n) + " centres, but the file (" + std::to_string(reader.getFileBytes()) +
                " bytes) cannot hold that many centre lines of at least 10 bytes");
  Eigen::Matrix3Xd centres(3, n);
  Eigen::VectorXd weights(n), shapes(n);
  for (int k = 0; k < n; ++k) {
    double row[5];
    reader.nextNumbers(5, row);
    const std::string which = "centre " + std::to_string(k);
    for (int c = 0; c < 3; ++c) checkMagnitude(reader, row[c], kMaxRbfCoordinateMm, which + ": coordinate");
    checkMagnitude(reader, row[3], kMaxRbfWeight, which + ": weight");
    if (!(row[4] > 0)) reader.fail("shape of centre " + std::to_string(k) + " must be > 0");
    if (!(row[4] >= kMinRbfShape && row[4] <= kMaxRbfShape)) {
      std::ostringstream text;
      text << "shape of centre " << k << " is " << row[4] << " mm^-2, expected " << kMinRbfShape << " to "
           << kMaxRbfShape << " (see rbf_file.h)";
      reader.fail(text.str());
    }
    centres.col(k) << row[0], row[1], row[2];
    weights[k] = row[3];
    shapes[k] = row[4];
  }
  reader.expectEnd("more centre lines than the " + std::to_string(n) + " declared by 'centres' on line " +
                   std::to_string(count_line) + " (expected the end of the file)");
  s.field = GaussianField(offset, centres, weights, shapes, cutoff);
  return s;
}

}  // namespace

}  // namespace rbfmuscle
