// SPDX-License-Identifier: Apache-2.0
/// @file
/// rbfmuscle.Model: a model loaded as `rbfmuscle run` loads it, run through its motion or
/// stepped with coordinates from Python; outputs, the run's table and the frame's geometry as
/// NumPy arrays. Frames run without the GIL.
#include "loaded_model.h"
#include "model/motion.h"
#include "model/skeleton.h"
#include "python_support.h"

#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace rbfmuscle::python {
namespace {

class PyModel {
 public:
  PyModel(const std::string& path, const std::vector<std::string>& overrides, const std::string& motion,
          const std::vector<std::string>& plugins) {
    const ModelSource source{path, plugins, overrides, motion, {}};
    const std::string library_directory = libraryDirectory();
    try {
      py::gil_scoped_release release;
      loaded_ = std::make_unique<LoadedModel>(source, library_directory,
                                              [](const Component&, int, int, bool done) {
                                                if (!done) checkPythonSignals();
                                              });
    } catch (const PythonErrorSet&) {
      throw py::error_already_set();
    }
  }

  const Model& model() const { return loaded_->getModel(); }

  /// Coordinates (rad; mm for translations) from a sequence in skeleton order, or from a dict
  /// by name (the others at their rest values, as a motion leaves them).
  Eigen::VectorXd readCoordinates(const py::object& coordinates) const {
    const Skeleton& skeleton = model().getSkeleton();
    const std::vector<std::string>& names = skeleton.getCoordinateNames();
    Eigen::VectorXd q = skeleton.getRestCoordinateValues();
    if (py::isinstance<py::dict>(coordinates)) {
      for (const auto& [key, value] : coordinates.cast<py::dict>()) {
        const std::string name = py::str(key);
        const int index = skeleton.findCoordinateIndex(name);
        if (index < 0) throw py::key_error("no coordinate '" + name + "' (coordinates: " + joined(names) + ")");
        try {
          q[index] = value.cast<double>();
        } catch (const py::cast_error&) {
          throw py::type_error("coordinate '" + name + "': expected a number, got " +
                               std::string(py::str(py::type::of(value).attr("__name__"))));
        }
      }
    } else {
      const auto values = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(coordinates);
      if (!values || values.ndim() != 1 || values.size() != static_cast<py::ssize_t>(names.size()))
        throw py::value_error("coordinates: expected " + std::to_string(names.size()) + " values (" + joined(names) +
                              ") or a dict by name");
      for (py::ssize_t i = 0; i < values.size(); ++i) q[i] = values.at(i);
    }
    for (Eigen::Index i = 0; i < q.size(); ++i)
      if (!std::isfinite(q[i]) || std::abs(q[i]) > kMaxCoordinate_rad)
        throw py::value_error("coordinate '" + names[static_cast<std::size_t>(i)] + "' = " + std::to_string(q[i]) +
                              ": expected a finite value of magnitude ≤ 1e4 (rad, or mm for a translation)");
    return q;
  }

  void step(const py::object& coordinates, std::optional<double> time_s, bool geometry) {
    const Eigen::VectorXd q = readCoordinates(coordinates);
    py::gil_scoped_release release;
    const auto lock = claim();
    loaded_->step(time_s.value_or(loaded_->getSession().getNumFrames()), q, geometry);
  }

  py::dict run(bool geometry) {
    bool stopped = false;
    {
      py::gil_scoped_release release;
      const auto lock = claim();
      loaded_->reset();
      const Motion& motion = model().getMotion();
      for (int frame = 0; frame < motion.getNumFrames() && !stopped; ++frame) {
        loaded_->step(motion.getTime(frame), motion.getCoordinates(frame), geometry);
        try {
          checkPythonSignals();
        } catch (const PythonErrorSet&) {
          stopped = true;
        }
      }
    }
    if (stopped) throw py::error_already_set();
    return table();
  }

  void reset() {
    py::gil_scoped_release release;
    const auto lock = claim();
    loaded_->reset();
  }

  /// The table of the frames stepped since the last reset or run: column → 1-D array.
  py::dict table() const {
    const auto lock = claim();
    const StorageTable& table = loaded_->getSession().getTable();
    py::dict columns;
    for (std::size_t c = 0; c < table.column_labels.size(); ++c) {
      py::array_t<double> column(static_cast<py::ssize_t>(table.rows.size()));
      double* values = column.mutable_data();
      for (std::size_t r = 0; r < table.rows.size(); ++r) values[r] = table.rows[r][c];
      columns[py::str(table.column_labels[c])] = std::move(column);
    }
    return columns;
  }

  py::object output(const std::string& label) const {
    const auto lock = claim();
    return valueOf(findOutput(label));
  }

  py::dict outputs() const {
    const auto lock = claim();
    py::dict values;
    for (const auto& component : model().getComponents())
      for (const AbstractOutput* output : component->getOutputs())
        values[py::str(component->getName() + "." + output->getName())] = valueOf(*output);
    return values;
  }

  py::dict outputUnits() const {
    py::dict units;
    for (const auto& component : model().getComponents())
      for (const AbstractOutput* output : component->getOutputs())
        units[py::str(component->getName() + "." + output->getName())] = output->getUnit();
    return units;
  }

  py::dict geometry() const {
    const auto lock = claim();
    py::dict all;
    for (const FrameGeometry& part : loaded_->getFrameGeometry()) all[py::str(part.name)] = describe(part);
    return all;
  }

  py::tuple surface(const std::string& name) const {
    const auto lock = claim();
    const FrameGeometry part = findGeometry(name);
    return py::make_tuple(pointsAsRows(part.vertices_mm), indicesAsRows(part.triangles));
  }

  /// The fibres of a component (geometry NAME_fibres): count × points × 3 when every fibre has
  /// as many points, else a list of points × 3 arrays.
  py::object fibres(const std::string& name) const {
    const auto lock = claim();
    const FrameGeometry part = findGeometry(name + "_fibres");
    bool equal = true;
    for (const auto& line : part.polylines) equal = equal && line.size() == part.polylines.front().size();
    if (equal) {
      const py::ssize_t count = static_cast<py::ssize_t>(part.polylines.size());
      const py::ssize_t points = count ? static_cast<py::ssize_t>(part.polylines.front().size()) : 0;
      py::array_t<double> all({count, points, py::ssize_t{3}});
      auto view = all.mutable_unchecked<3>();
      for (py::ssize_t i = 0; i < count; ++i)
        for (py::ssize_t j = 0; j < points; ++j)
          for (py::ssize_t k = 0; k < 3; ++k) view(i, j, k) = part.vertices_mm(k, part.polylines[i][j]);
      return std::move(all);
    }
    py::list lines;
    for (const auto& line : part.polylines) lines.append(polylinePoints(part, line));
    return std::move(lines);
  }

  int frames() const { return loaded_->getSession().getNumFrames(); }

  /// X_GB of a body at the coordinates last stepped: 4×4, translation in mm.
  py::array_t<double> bodyTransform(const std::string& body) const {
    const auto lock = claim();
    const Skeleton& skeleton = model().getSkeleton();
    const int index = skeleton.findBodyIndex(body);
    if (index < 0) throw py::key_error("no body '" + body + "' (bodies: " + joined(skeleton.getBodyNames()) + ")");
    const Eigen::Matrix4d X_GB = skeleton.getBodyTransform(index).matrix();
    py::array_t<double> out({py::ssize_t{4}, py::ssize_t{4}});
    auto view = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < 4; ++i)
      for (py::ssize_t j = 0; j < 4; ++j) view(i, j) = X_GB(i, j);
    return out;
  }

 private:
  static std::string joined(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
    return text.empty() ? "none" : text;
  }

  /// The model is stepped by one thread at a time; a second one is refused, not queued.
  std::unique_lock<std::mutex> claim() const {
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock())
      throw std::runtime_error("this rbfmuscle.Model is in use by another thread (use one Model per thread)");
    return lock;
  }

  const AbstractOutput& findOutput(const std::string& label) const {
    try {
      return loaded_->findOutput(label);
    } catch (const FrameworkError& error) {
      throw py::key_error(error.what());
    }
  }

  FrameGeometry findGeometry(const std::string& name) const {
    std::string names;
    for (FrameGeometry& part : loaded_->getFrameGeometry()) {
      if (part.name == name) return std::move(part);
      names += (names.empty() ? "" : ", ") + part.name;
    }
    throw py::key_error("no geometry '" + name + "' in the last frame (geometry: " + (names.empty() ? "none" : names) +
                        ")");
  }

  /// A scalar output as numpy.float64, a vector output as a 1-D array (copies).
  static py::object valueOf(const AbstractOutput& output) {
    std::vector<double> values;
    output.appendValues(values);
    if (output.getTypeName() == std::string("double"))
      return py::module_::import("numpy").attr("float64")(values.empty() ? NAN : values.front());
    py::array_t<double> array(static_cast<py::ssize_t>(values.size()));
    std::copy(values.begin(), values.end(), array.mutable_data());
    return std::move(array);
  }

  static py::array_t<double> polylinePoints(const FrameGeometry& part, const std::vector<int>& line) {
    py::array_t<double> points({static_cast<py::ssize_t>(line.size()), py::ssize_t{3}});
    auto view = points.mutable_unchecked<2>();
    for (std::size_t j = 0; j < line.size(); ++j)
      for (py::ssize_t k = 0; k < 3; ++k) view(static_cast<py::ssize_t>(j), k) = part.vertices_mm(k, line[j]);
    return points;
  }

  static py::dict describe(const FrameGeometry& part) {
    py::dict d;
    d["vertices_mm"] = pointsAsRows(part.vertices_mm);
    d["triangles"] = indicesAsRows(part.triangles);
    py::list lines;
    for (const auto& line : part.polylines) lines.append(py::array_t<int>(static_cast<py::ssize_t>(line.size()), line.data()));
    d["polylines"] = std::move(lines);
    return d;
  }

  std::unique_ptr<LoadedModel> loaded_;
  mutable std::mutex mutex_;
};

py::array_t<double> motionCoordinates(const Motion& motion, std::size_t coordinates) {
  py::array_t<double> q({static_cast<py::ssize_t>(motion.getNumFrames()), static_cast<py::ssize_t>(coordinates)});
  auto view = q.mutable_unchecked<2>();
  for (int f = 0; f < motion.getNumFrames(); ++f)
    for (std::size_t c = 0; c < coordinates; ++c) view(f, static_cast<py::ssize_t>(c)) = motion.getCoordinates(f)[c];
  return q;
}

}  // namespace

void bindModel(py::module_& m) {
  py::class_<PyModel>(m, "Model", R"(A model file loaded as `rbfmuscle run` loads it, its components initialised.

Model(path, overrides=[], motion="", plugins=[]): overrides are
"COMPONENT[/SUBCOMPONENT].PROPERTY=VALUE" (--set), motion a motion file replacing the model's (--motion), plugins loaded before the
model's own (-L). Errors raise rbfmuscle.Error with the command line's message.)")
      .def(py::init<const std::string&, const std::vector<std::string>&, const std::string&,
                    const std::vector<std::string>&>(),
           py::arg("path"), py::arg("overrides") = std::vector<std::string>{}, py::arg("motion") = std::string(),
           py::arg("plugins") = std::vector<std::string>{})
      .def_property_readonly("name", [](const PyModel& self) { return self.model().getDocument().name; })
      .def_property_readonly("path", [](const PyModel& self) { return self.model().getDocument().path; },
                             "the model file as given")
      .def_property_readonly("coordinate_names",
                             [](const PyModel& self) { return self.model().getSkeleton().getCoordinateNames(); })
      .def_property_readonly("body_names", [](const PyModel& self) { return self.model().getSkeleton().getBodyNames(); })
      .def_property_readonly("rest_coordinates",
                             [](const PyModel& self) {
                               const Eigen::VectorXd& q = self.model().getSkeleton().getRestCoordinateValues();
                               return py::array_t<double>(q.size(), q.data());
                             })
      .def_property_readonly("component_names",
                             [](const PyModel& self) {
                               std::vector<std::string> names;
                               for (const auto& c : self.model().getComponents()) names.push_back(c->getName());
                               return names;
                             })
      .def_property_readonly("output_units", &PyModel::outputUnits,
                             "unit of every output, by COMPONENT.OUTPUT (all outputs, reported or not)")
      .def_property_readonly("motion_path", [](const PyModel& self) { return self.model().getMotion().getPath(); })
      .def_property_readonly("motion_times",
                             [](const PyModel& self) {
                               const Motion& motion = self.model().getMotion();
                               py::array_t<double> t(motion.getNumFrames());
                               for (int f = 0; f < motion.getNumFrames(); ++f) t.mutable_data()[f] = motion.getTime(f);
                               return t;
                             },
                             "time of each frame of the motion (s)")
      .def_property_readonly("motion_coordinates",
                             [](const PyModel& self) {
                               return motionCoordinates(self.model().getMotion(),
                                                        self.model().getSkeleton().getCoordinateNames().size());
                             },
                             "coordinates of each frame of the motion, frames × coordinates (rad; mm for translations)")
      .def_property_readonly("frame", &PyModel::frames, "frames stepped since the last reset or run")
      .def("step", &PyModel::step, py::arg("coordinates"), py::kw_only(), py::arg("time") = py::none(),
           py::arg("geometry") = false,
           R"(Steps one frame: the skeleton at `coordinates` (a sequence in coordinate_names order, or a
dict by name with the others at rest; rad, mm for translations), every component updated
without the GIL, the row recorded. `time` (s) defaults to the frame number; with
geometry=True the components prepare their surface and fibres (surface(), fibres()).)")
      .def("run", &PyModel::run, py::kw_only(), py::arg("geometry") = false,
           "Runs the whole motion from frame 0, as `rbfmuscle run` does, and returns its table (see table()).")
      .def("reset", &PyModel::reset, "Forgets the frames stepped: the next step is frame 0.")
      .def("table", &PyModel::table,
           "The frames since the last reset or run as a dict column -> 1-D float64 array, the columns of "
           "outputs.csv: time, the coordinates, COMPONENT.OUTPUT (COMPONENT.OUTPUT_i per element of a vector).")
      .def("outputs", &PyModel::outputs,
           "Every output of the last frame by COMPONENT.OUTPUT: numpy.float64, or a 1-D array for a vector.")
      .def("output", &PyModel::output, py::arg("name"), "One output of the last frame (see outputs()).")
      .def("geometry", &PyModel::geometry,
           "The last frame's geometry (ground, mm) by name: vertices_mm (n×3), triangles (m×3), polylines.")
      .def("surface", &PyModel::surface, py::arg("component"),
           "The component's surface in the last frame: (vertices_mm n×3, triangles m×3).")
      .def("body_transform", &PyModel::bodyTransform, py::arg("body"),
           "Pose X_GB of a body in ground at the coordinates last stepped (the rest pose before the first step): "
           "a 4×4 array, translation in mm.")
      .def("fibres", &PyModel::fibres, py::arg("component"),
           "The component's fibres in the last frame (ground, mm): fibres × points × 3.");
}

}  // namespace rbfmuscle::python
