// SPDX-License-Identifier: Apache-2.0
/// @file
/// rbfmuscle._rbfmuscle, the compiled half of the Python module rbfmuscle: the model
/// (model_binding.cpp), the fit (fit_binding.cpp) and the errors. Every error the command line
/// prints as "rbfmuscle: error: MESSAGE" raises rbfmuscle.Error(MESSAGE) (rbfmuscle.UsageError
/// for a bad argument, one the command line answers with its usage).
#include "framework/framework_error.h"
#include "framework/interrupt.h"
#include "host/usage_error.h"
#include "python_support.h"

#include <exception>
#include <new>

namespace rbfmuscle::python {
void bindModel(py::module_& m);
void bindFit(py::module_& m);
}  // namespace rbfmuscle::python

PYBIND11_MODULE(_rbfmuscle, m) {
  namespace py = pybind11;
  m.doc() = "rbfmuscle: Gaussian RBF muscle surfaces on a Simbody skeleton (compiled part).";
  static py::exception<rbfmuscle::FrameworkError> error(m, "Error", PyExc_RuntimeError);
  static py::exception<rbfmuscle::UsageError> usage_error(m, "UsageError", error.ptr());
  error.attr("__module__") = "rbfmuscle";
  usage_error.attr("__module__") = "rbfmuscle";
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const rbfmuscle::UsageError& e) {
      usage_error(e.what());
    } catch (const rbfmuscle::Interrupted& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const py::builtin_exception&) {
      throw;  // pybind11's own (ValueError, KeyError, ...)
    } catch (const py::error_already_set&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw;  // MemoryError
    } catch (const std::exception& e) {
      error(e.what());  // FrameworkError, ModelError, MeshError, std::runtime_error, ...
    }
  });
  rbfmuscle::python::bindModel(m);
  rbfmuscle::python::bindFit(m);
}
