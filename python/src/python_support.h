// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// What the bindings share: Ctrl-C while C++ works without the GIL, where the plugin is, and
/// Eigen point sets as NumPy arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>

#include <string>

namespace rbfmuscle::python {

namespace py = pybind11;

/// Thrown out of C++ work when a Python signal handler raised (KeyboardInterrupt on Ctrl-C);
/// the Python error is set on the thread, so the binding throws py::error_already_set once it
/// holds the GIL again. Not a std::exception: no `catch (const std::exception&)` on the way
/// turns it into a message.
struct PythonErrorSet {};

/// Runs Python's signal handlers (taking the GIL for it); throws PythonErrorSet when one raised.
void checkPythonSignals();

/// The directory of the host's libraries (build/lib), where the plugin is found as the host
/// finds it in its ../lib.
std::string libraryDirectory();

/// 3×n points as an n×3 array (a copy).
py::array_t<double> pointsAsRows(const Eigen::Matrix3Xd& points);
/// 3×n indices as an n×3 int32 array (a copy).
py::array_t<int> indicesAsRows(const Eigen::Matrix3Xi& indices);

}  // namespace rbfmuscle::python
