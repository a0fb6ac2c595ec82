// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Helpers shared by the model tests: scratch files, error-message checks, and
/// a minimal reader for the vertices of the binary PLY meshes in models/.
#include <gtest/gtest.h>
#include <Eigen/Core>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "model/model_error.h"

namespace rbfmuscle::test {

/// A scratch file in the build tree, removed when the object goes out of scope.
class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : path_(std::string(RBFMUSCLE_BINARY_DIR) + "/model_test_" + name) {}
  ~TempFile() { std::remove(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }
  void write(const std::string& text) const { std::ofstream(path_) << text; }

 private:
  std::string path_;
};

/// Expects `f` to throw ModelError whose message contains every one of `parts`.
template <typename F>
void expectModelError(F f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "expected ModelError";
  } catch (const ModelError& e) {
    const std::string what = e.what();
    for (const auto& p : parts)
      EXPECT_NE(what.find(p), std::string::npos) << "message: " << what << "\nmissing: " << p;
  }
}

/// Vertices (3 x n) of a binary little-endian PLY whose vertex element starts
/// with `float x`, `float y`, `float z` and has no other properties.
inline Eigen::Matrix3Xd readPlyVertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  long n = -1;
  bool in_vertex = false;
  std::vector<std::string> props;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream s(line);
    std::string word;
    s >> word;
    if (word == "format" && line.find("binary_little_endian") == std::string::npos)
      throw std::runtime_error(path + ": not binary little endian");
    if (word == "element") {
      std::string kind;
      long count = 0;
      s >> kind >> count;
      in_vertex = kind == "vertex";
      if (in_vertex) n = count;
    } else if (word == "property" && in_vertex) {
      props.push_back(line);
    }
  }
  if (n < 0 || props != std::vector<std::string>{"property float x", "property float y",
                                                  "property float z"})
    throw std::runtime_error(path + ": unexpected PLY vertex layout");
  std::vector<float> xyz(static_cast<std::size_t>(3 * n));
  in.read(reinterpret_cast<char*>(xyz.data()), static_cast<std::streamsize>(xyz.size() * sizeof(float)));
  if (!in) throw std::runtime_error(path + ": truncated vertex data");
  Eigen::Matrix3Xd v(3, n);
  for (long i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) v(k, i) = xyz[static_cast<std::size_t>(3 * i + k)];
  return v;
}

}  // namespace rbfmuscle::test
