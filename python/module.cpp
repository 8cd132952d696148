// fretbem's Python API (pybind11): scenarios from INI files or dicts, the Model and its
// Stepper driven step by step, fields as numpy arrays in the `[ny][nx]` layout of result.h5
// (views without copies where the field is stored as such), height maps passed in with an
// explicit axis order, the Ciavarella–Jäger shortcut and the Greenwood–Williamson model.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "fretbem/contact/monotone_shortcut.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/elastic/closed_forms.hpp"
#include "fretbem/history/cycle_summary.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/preflight.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/io/run_output.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/study/greenwood_williamson.hpp"

namespace py = pybind11;
using namespace fretbem;

namespace {

// A Field (nx x ny, column-major: x fastest) seen as a numpy (ny, nx) C-ordered array that
// shares its memory; `owner` keeps the storage alive.
// Read-only: the solver's own state. NaN written into model.surface would reach the solver
// as "normal solver did not converge: residual nan", naming nothing; copy to modify.
template <class Array>
py::array view_yx(const Array& f, py::handle owner) {
  using T = typename Array::Scalar;
  const auto s = static_cast<py::ssize_t>(sizeof(T));
  py::array a = py::array_t<T>({py::ssize_t(f.cols()), py::ssize_t(f.rows())},
                               {s * py::ssize_t(f.rows()), s}, f.data(), owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::array copy_yx(const Field& f) {
  return view_yx(f, py::none()).attr("copy")();
}

// A height map given as numpy, in the order the user names: "yx" (rows along y, as result.h5
// and fretbem's files) or "xy" (first index along x, as SurfaceTopography's arrays).
Field field_from(py::array_t<double, py::array::forcecast> a, const std::string& layout,
                 const Grid& g) {
  if (a.ndim() != 2) throw InputError("surface: a 2-D array is needed");
  if (layout != "yx" && layout != "xy")
    throw InputError("layout = '" + layout + "' is not one of yx|xy");
  const bool yx = layout == "yx";
  const auto nx = yx ? a.shape(1) : a.shape(0), ny = yx ? a.shape(0) : a.shape(1);
  if (nx != g.nx || ny != g.ny)
    throw InputError("surface: array of " + std::to_string(nx) + " x " + std::to_string(ny) +
                     " nodes (x x y, layout " + layout + ") on a grid of " + std::to_string(g.nx) +
                     " x " + std::to_string(g.ny));
  const auto r = a.unchecked<2>();
  Field z(g.nx, g.ny);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) z(i, j) = yx ? r(j, i) : r(i, j);
  if (!z.allFinite()) throw InputError("surface: the array holds NaN or Inf");
  return z;
}

py::dict record_dict(const StepRecord& r) {
  py::dict d;
  const auto vals = r.values();
  const auto& cols = StepRecord::columns();
  for (std::size_t i = 0; i < cols.size(); ++i) d[py::str(cols[i])] = vals[i];
  return d;
}

py::dict cycle_dict(const CycleRow& c) {
  py::dict d;
  const auto vals = c.values();
  const auto& cols = CycleRow::columns();
  for (std::size_t i = 0; i < cols.size(); ++i) d[py::str(cols[i])] = vals[i];
  d["cycle"] = c.cycle, d["steps"] = c.steps, d["contact_nodes"] = c.contact_nodes;
  return d;
}

// The Model with the Python objects it depends on.
struct PyModel {
  std::unique_ptr<Model> model;
};

// A stepper with its own counts: two steppers on one model share the model's operators (and
// their convolution counter), so each keeps the sum of its own steps' convolutions.
struct PyStepper {
  std::shared_ptr<PyModel> owner;
  std::unique_ptr<Stepper> stepper;
  std::size_t next = 0;
  std::int64_t convolutions = 0;
  // The rows of cycles.csv, by the code that writes that file.
  std::unique_ptr<CycleAccumulator> accumulator;
  std::vector<CycleRow> cycles;

  py::dict advance() {
    if (next >= stepper->steps()) throw py::stop_iteration();
    const StepRecord rec = stepper->advance(next++);
    convolutions += rec.convolutions;
    if (auto c = accumulator->add(rec)) cycles.push_back(*c);
    if (next == stepper->steps())
      if (auto c = accumulator->finish()) cycles.push_back(*c);
    return record_dict(rec);
  }
};

// Errors of a scenario built in Python name the call that built it, as the CLI names the file.
Scenario from_text(const std::string& text, const std::string& name, const std::string& base,
                   const std::vector<std::string>& overrides) {
  return parse_scenario(text, name, base, overrides);
}

// A Python value as INI text: bools as true/false, lists and tuples comma-separated (as
// output.fields = pressure, state), whole floats (32.0, numpy's too) as integers so that integer
// keys accept them, other numbers through repr (shortest round-trip spelling).
std::string ini_value(const py::handle& v) {
  // Imported per call (cached in sys.modules): a static py::object outlives the interpreter.
  const py::object numbers = py::module_::import("numbers");
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::string out;
    for (const auto& item : v) out += (out.empty() ? "" : ", ") + ini_value(item);
    return out;
  }
  if (py::isinstance(v, numbers.attr("Integral"))) return py::str(v).cast<std::string>();
  if (py::isinstance(v, numbers.attr("Real"))) {
    const double x = v.cast<double>();
    // Below 2^53 a whole double is an exact integer.
    if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9007199254740992.0)
      return std::to_string(static_cast<long long>(x));
    return py::repr(py::float_(x)).cast<std::string>();
  }
  return py::str(v).cast<std::string>();
}

// {"material": {"E": 210e9, ...}, ...} -> INI text.
// (A stream, not string concatenation: GCC 12 warns falsely (-Wrestrict) on the latter here.)
std::string ini_of(const py::dict& d) {
  std::ostringstream text;
  for (auto [section, keys] : d) {
    text << "[" << py::str(section).cast<std::string>() << "]\n";
    for (auto [k, v] : keys.cast<py::dict>())
      text << py::str(k).cast<std::string>() << " = " << ini_value(v) << "\n";
  }
  return text.str();
}

void bind_scenario(py::module_& m) {
  py::class_<Scenario>(m, "Scenario", "A validated scenario (every key checked, SI units).")
      .def_static(
          "from_file",
          [](const std::string& path, const std::vector<std::string>& overrides) {
            return load_scenario(path, overrides);
          },
          py::arg("path"), py::arg("overrides") = std::vector<std::string>{},
          "Reads an INI scenario; overrides are 'section.key=value' strings.")
      .def_static(
          "from_dict",
          [](const py::dict& d, const std::string& base, const std::vector<std::string>& o) {
            return from_text(ini_of(d), "Scenario.from_dict", base, o);
          },
          py::arg("sections"), py::arg("base_dir") = ".",
          py::arg("overrides") = std::vector<std::string>{},
          "Builds a scenario from {'section': {'key': value}}; relative paths against base_dir.")
      .def_static("from_text", &from_text, py::arg("text"), py::arg("name") = "Scenario.from_text",
                  py::arg("base_dir") = ".", py::arg("overrides") = std::vector<std::string>{})
      .def_property_readonly(
          "text", [](const Scenario& s) { return s.resolved_text; },
          "The resolved scenario: every key with its final value.")
      .def_property_readonly(
          "shape", [](const Scenario& s) { return py::make_tuple(s.grid.ny, s.grid.nx); },
          "(ny, nx), the shape of every field array")
      .def_property_readonly(
          "spacing", [](const Scenario& s) { return s.grid.h; }, "h (m)")
      .def_property_readonly("E_star", [](const Scenario& s) { return s.material.E_star(); })
      .def_property_readonly("G_star", [](const Scenario& s) { return s.material.G_star(); })
      .def_property_readonly("mu", [](const Scenario& s) { return s.material.mu; });
}

void bind_model(py::module_& m) {
  py::class_<PyModel, std::shared_ptr<PyModel>>(m, "Model", "Grid, surface, operators and solvers.")
      .def(py::init([](const Scenario& sc, py::object surface, const std::string& layout) {
             auto pm = std::make_shared<PyModel>();
             pm->model = build_model(sc);
             if (!surface.is_none()) {
               pm->model->surface0 = field_from(surface, layout, sc.grid);
               pm->model->surface = pm->model->surface0;
               // The checks a height-map file meets (heights of 1e200 m ran into "residual
               // -nan" instead).
               try {
                 check_before_solve(sc, pm->model->path, pm->model->surface0);
               } catch (const InputError& e) {
                 throw InputError(std::string("Model(surface=...): ") + e.what());
               }
             }
             return pm;
           }),
           py::arg("scenario"), py::arg("surface") = py::none(), py::arg("layout") = "yx",
           "surface: optional height map (m, peaks positive) replacing the scenario's; "
           "layout 'yx' (array[j, i] at x_i, y_j) or 'xy' (array[i, j]).")
      .def_property_readonly(
          "surface",
          [](py::object self) { return view_yx(self.cast<PyModel&>().model->surface, self); },
          "current indenter height (m), [ny][nx], a view")
      .def_property_readonly("steps", [](const PyModel& p) { return p.model->path.steps.size(); });
}

void bind_stepper(py::module_& m) {
  py::class_<PyStepper>(m, "Stepper", "Walks the load path one step at a time.")
      .def(py::init([](std::shared_ptr<PyModel> pm) {
             // pybind11 passes None as an empty holder: unchecked, Stepper(None) is a SIGSEGV.
             if (!pm)
               throw py::type_error("Stepper(model): model must be a fretbem.Model, not None");
             PyStepper s;
             s.owner = pm;
             s.stepper = std::make_unique<Stepper>(*pm->model);
             const Scenario& sc = pm->model->scenario;
             s.accumulator = std::make_unique<CycleAccumulator>(sc.load.path, sc.grid.h);
             return s;
           }),
           py::arg("model"))
      .def("advance", &PyStepper::advance,
           "Runs the next step; returns its time-series row as a dict (StopIteration at the "
           "end).")
      .def("__iter__", [](PyStepper& s) -> PyStepper& { return s; })
      .def("__next__", &PyStepper::advance)
      .def_property_readonly("next_step", [](const PyStepper& s) { return s.next; })
      .def_property_readonly(
          "convolutions", [](const PyStepper& s) { return s.convolutions; },
          "FFT convolutions this stepper's steps used (its own, also when another stepper "
          "shares the model)")
      .def_property_readonly(
          "cycles",
          [](const PyStepper& s) {
            py::list out;
            for (const auto& c : s.cycles) out.append(cycle_dict(c));
            return out;
          },
          "The load cycles finished so far, one dict per cycle with the columns of cycles.csv "
          "(dissipated_energy and loop_area in J, Fx_amplitude in N, Ux_amplitude in m, ...); "
          "the last cycle is closed by the path's last step. Ramps have none.")
      .def(
          "cycles_array",
          [](const PyStepper& s) {
            const auto cols = py::ssize_t(CycleRow::columns().size());
            py::array_t<double> a({py::ssize_t(s.cycles.size()), cols});
            auto w = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < s.cycles.size(); ++i) {
              const auto v = s.cycles[i].values();
              for (py::ssize_t j = 0; j < cols; ++j) w(py::ssize_t(i), j) = v[std::size_t(j)];
            }
            return a;
          },
          "The finished cycles as a (cycles, columns) float array, columns as "
          "fretbem.cycle_columns (the columns of cycles.csv).")
      .def_property_readonly(
          "pressure",
          [](py::object self) {
            return view_yx(self.cast<PyStepper&>().stepper->state().pressure, self);
          },
          "p (Pa), [ny][nx], a view valid until the next step changes it")
      .def_property_readonly(
          "state",
          [](py::object self) {
            return view_yx(self.cast<PyStepper&>().stepper->state().state, self);
          },
          "0 open, 1 stick, 2 slip (uint8), [ny][nx], a view")
      .def(
          "field",
          [](const PyStepper& s, const std::string& name) {
            const auto f = output_fields({name}, s.stepper->state(), *s.owner->model);
            if (f.empty())
              throw InputError("field '" + name +
                               "' is not one of pressure, traction_x, traction_y, state, "
                               "slip_x, slip_y, dissipation, wear");
            return copy_yx(f.begin()->second);
          },
          py::arg("name"), "A copy of an output field in global x/y components, [ny][nx].");
}

void bind_closed_forms(py::module_& m) {
  auto gw = m.def_submodule("gw", "Greenwood–Williamson model of the paper (eqs. 11–15, 25–28)");
  gw.def("stick_area_ratio", &gw::stick_area_ratio, py::arg("b"));
  gw.def("force_ratio", &gw::force_ratio, py::arg("b"));
  gw.def("stick_force_ratio", &gw::stick_force_ratio, py::arg("b"));
  gw.def("slip_force_ratio", &gw::slip_force_ratio, py::arg("b"));
  gw.def("b_of_force_ratio", &gw::b_of_force_ratio, py::arg("f"));
  gw.def("stiffness_ratio_flat", &gw::stiffness_ratio_flat, py::arg("f"));
  gw.def("stiffness_ratio_fractal", &gw::stiffness_ratio_fractal, py::arg("f"), py::arg("hurst"));
  auto sphere = m.def_submodule(
      "sphere", "Hertz, Cattaneo and Mindlin closed forms of a sphere on a flat (SI units)");
  sphere.def("hertz_contact_radius", &closed_forms::hertz_contact_radius, py::arg("force"),
             py::arg("radius"), py::arg("E_star"));
  sphere.def("hertz_peak_pressure", &closed_forms::hertz_peak_pressure, py::arg("force"),
             py::arg("a"));
  sphere.def("hertz_approach", &closed_forms::hertz_approach, py::arg("a"), py::arg("radius"));
  sphere.def("hertz_force", &closed_forms::hertz_force, py::arg("a"), py::arg("radius"),
             py::arg("E_star"));
  sphere.def("full_sliding_shift", &closed_forms::full_sliding_shift, py::arg("mu"),
             py::arg("approach"), py::arg("E_star"), py::arg("G_star"));
  sphere.def("cattaneo_stick_ratio", &closed_forms::cattaneo_stick_ratio, py::arg("q"));
  sphere.def("cattaneo_shift_ratio", &closed_forms::cattaneo_shift_ratio, py::arg("q"));
  sphere.def("cattaneo_force_ratio", &closed_forms::cattaneo_force_ratio, py::arg("shift_ratio"));
  sphere.def("mindlin_energy_per_cycle", &closed_forms::mindlin_energy_per_cycle, py::arg("q"),
             py::arg("mu"), py::arg("P"), py::arg("ustar"));
  m.def(
      "ciavarella_jaeger",
      [](PyStepper& s, double Ft) {
        const Model& model = *s.owner->model;
        const InterfaceState& st = s.stepper->state();
        if (s.next == 0) throw InputError("ciavarella_jaeger: advance() the normal loading first");
        const ShortcutResult r = ciavarella_jaeger_force(
            *model.normal, model.surface, st.pressure, st.normal_force, st.indentation,
            model.scenario.material.mu, model.half_space->tangential_ratio(), Ft);
        py::dict d;
        d["traction"] = copy_yx(r.traction);
        d["shift"] = r.shift;
        d["force"] = r.force;
        return d;
      },
      py::arg("stepper"), py::arg("force"),
      "The Ciavarella–Jäger solution at tangential force F_t (N) on the stepper's current "
      "normal contact: {'traction' (Pa, [ny][nx]), 'shift' (m), 'force' (N)}.");
}

// InputError and SolverError as Python exceptions whose message survives bytes that are not
// UTF-8 (a scenario of binary garbage quotes its line, and its message must not be empty).
void register_errors(py::module_& m) {
  static py::exception<InputError> input(m, "InputError", PyExc_ValueError);
  static py::exception<SolverError> solver(m, "SolverError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    auto raise = [](const py::object& type, const char* what) {
      PyObject* msg = PyUnicode_DecodeUTF8(what, Py_ssize_t(std::strlen(what)), "replace");
      PyErr_SetObject(type.ptr(), msg);
      Py_XDECREF(msg);
    };
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      raise(input, e.what());
    } catch (const SolverError& e) {
      raise(solver, e.what());
    }
  });
}

}  // namespace

PYBIND11_MODULE(_fretbem, m) {
  m.doc() = "fretbem: frictional contact of rough elastic surfaces under load histories";
  m.attr("__version__") = FRETBEM_VERSION;
  m.attr("cycle_columns") = CycleRow::columns();
  register_errors(m);
  bind_scenario(m);
  bind_model(m);
  bind_stepper(m);
  bind_closed_forms(m);
}
