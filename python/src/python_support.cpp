// SPDX-License-Identifier: Apache-2.0
#include "python_support.h"

#include "host/model_loading.h"

#include <dlfcn.h>

#include <cstring>
#include <filesystem>

namespace rbfmuscle::python {

void checkPythonSignals() {
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) throw PythonErrorSet{};
}

std::string libraryDirectory() {
  // The directory of librbfmuscle_host.so, which holds the plugin as well.
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&readModelSource), &info) == 0 || info.dli_fname == nullptr) return {};
  return std::filesystem::path(info.dli_fname).parent_path().string();
}

py::array_t<double> pointsAsRows(const Eigen::Matrix3Xd& points) {
  py::array_t<double> rows({static_cast<py::ssize_t>(points.cols()), py::ssize_t{3}});
  // Matrix3Xd stores x y z of each point in turn: the n×3 row-major layout.
  if (points.size() > 0) std::memcpy(rows.mutable_data(), points.data(), sizeof(double) * points.size());
  return rows;
}

py::array_t<int> indicesAsRows(const Eigen::Matrix3Xi& indices) {
  py::array_t<int> rows({static_cast<py::ssize_t>(indices.cols()), py::ssize_t{3}});
  if (indices.size() > 0) std::memcpy(rows.mutable_data(), indices.data(), sizeof(int) * indices.size());
  return rows;
}

}  // namespace rbfmuscle::python
