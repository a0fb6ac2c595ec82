// SPDX-License-Identifier: Apache-2.0
/// @file
/// rbfmuscle._fit: `rbfmuscle fit` from Python. The arguments are the command line's (the
/// Python wrapper builds them from keywords), so parsing, checks, fit, writing and every
/// message are the command's (host/fit_command.h). The fit runs without the GIL.
#include "host/fit_command.h"
#include "python_support.h"

#include <pybind11/stl.h>

#include <string>
#include <vector>

namespace rbfmuscle::python {

void bindFit(py::module_& m) {
  m.def(
      "_fit",
      [](const std::vector<std::string>& args) {
        const FitJob job = parseFitArguments(args, false);
        MeshFit fit;
        try {
          py::gil_scoped_release release;
          // Ctrl-C stops the fit after the round, as it stops the command.
          fit = runFitJob(job, [](const FitProgress&) { checkPythonSignals(); });
          writeFitOutputs(job, fit);
        } catch (const PythonErrorSet&) {
          throw py::error_already_set();
        }
        const TriangleMesh surface = fittedSurfaceInSourceFrame(fit);
        py::dict result;
        result["metrics_json"] = fit.surface.metrics_json;
        result["warnings"] = fit.warnings;
        result["stop_reason"] = fit.stop_reason;
        result["rounds"] = fit.rounds;
        result["surface_vertices_mm"] = pointsAsRows(surface.vertices_mm);
        result["surface_triangles"] = indicesAsRows(surface.triangles);
        return result;
      },
      py::arg("args"),
      "Runs `rbfmuscle fit ARGS` (without -o it writes nothing) and returns its figures and the "
      "extracted surface in the mesh's frame.");
}

}  // namespace rbfmuscle::python
