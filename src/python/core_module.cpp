// pybind11 module oraclemesh._core: the job contract for Python. The pure-Python package
// `oraclemesh` wraps it (dict in, Result with numpy arrays out).
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <thread>

#include "Error.h"
#include "domain/OpenCascadeWork.h"
#include "domain/brep/ShapeFiles.h"
#include "job/JobJson.h"
#include "job/OpenCascadeStall.h"
#include "job/Pipeline.h"

namespace py = pybind11;
using namespace oraclemesh;

namespace {

template <typename T, size_t N, typename Rows>
py::array_t<T> table(const Rows& rows, size_t columns = N) {
  py::array_t<T> out({rows.size(), columns});
  auto view = out.template mutable_unchecked<2>();
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = 0; j < columns; ++j) view(i, j) = static_cast<T>(rows[i][j]);
  return out;
}

template <typename T, typename Values>
py::array_t<T> column(const Values& values) {
  py::array_t<T> out(values.size());
  auto view = out.template mutable_unchecked<1>();
  for (size_t i = 0; i < values.size(); ++i) view(i) = static_cast<T>(values[i]);
  return out;
}

py::dict toPython(const JobResult& result) {
  const TetMesh& m = result.mesh;
  py::dict d;
  d["points"] = table<double, 3>(m.points);
  if (m.order() == 2) {
    // Corners then the six mid nodes 01, 12, 20, 03, 13, 23 (VTK / FreeCAD mid-node order).
    std::vector<std::array<int64_t, 10>> tet10(m.tets.size());
    for (size_t i = 0; i < m.tets.size(); ++i) {
      for (int k = 0; k < 4; ++k) tet10[i][k] = m.tets[i][k];
      for (int k = 0; k < 6; ++k) tet10[i][4 + k] = m.tet_mid_nodes[i][k];
    }
    d["tets"] = table<int64_t, 10>(tet10);
  } else {
    d["tets"] = table<int64_t, 4>(m.tets);
  }
  d["tet_materials"] = column<int32_t>(m.tet_materials);
  std::vector<std::array<int64_t, 3>> tri;
  std::vector<std::array<int32_t, 2>> sides;
  for (const BoundaryTriangle& t : m.boundary) {
    tri.push_back(t.v);
    sides.push_back({t.material_in, t.material_out});
  }
  d["boundary_triangles"] = table<int64_t, 3>(tri);
  d["boundary_materials"] = table<int32_t, 2>(sides);
  d["feature_edges"] = table<int64_t, 2>(m.feature_edges);
  d["feature_edge_curves"] = column<int32_t>(m.feature_edge_curves);
  d["vertex_dimension"] = column<int8_t>(m.vertex_dimension);
  py::list surfaces;
  for (size_t i = 0; i < result.surfaces.size(); ++i) {
    const MeshSurface& s = result.surfaces[i];
    std::vector<std::array<int64_t, 2>> faces;
    for (const ElementFace& f : s.faces) faces.push_back({f.tet, f.face});
    py::dict surface;
    surface["name"] = result.surface_names[i];
    surface["material"] = s.material;
    surface["other_material"] = s.other_material;
    surface["faces"] = table<int64_t, 2>(faces);
    surfaces.append(surface);
  }
  d["surfaces"] = surfaces;
  d["report"] = result.report.dump();
  return d;
}

// Runs with the GIL released so FreeCAD's GUI thread and Python threads keep going; the
// progress callback takes the GIL back. A callback returning False cancels the run.
py::dict run(const std::string& jobJson, const std::string& baseDirectory, py::object progress) {
  const JobSpec job = JobSpec::fromJsonText(jobJson, baseDirectory);
  RunControl* controlPtr = nullptr;
  // The callback's own exception, raised again once the core has stopped: the caller sees
  // what its callback did, not "cancelled".
  std::shared_ptr<py::error_already_set> callbackError;
  RunControl control(
      [&](const std::string& phase, double fraction) {
        if (progress.is_none()) return;
        py::gil_scoped_acquire gil;
        try {
          py::object answer = progress(phase, fraction);
          if (answer.is(py::bool_(false))) controlPtr->requestCancel();
          if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        } catch (py::error_already_set& e) {
          // A failing or interrupted callback must not unwind through CGAL: stop cleanly.
          if (!callbackError) callbackError = std::make_shared<py::error_already_set>(std::move(e));
          controlPtr->requestCancel();
        }
      },
      job.time_limit);
  controlPtr = &control;
  JobResult result;
  bool stoppedByCallback = false;
  {
    py::gil_scoped_release release;
    try {
      result = runJob(job, control);
    } catch (const Error&) {
      if (!callbackError) throw;
      stoppedByCallback = true;  // raised below, with the GIL held again
    }
  }
  if (stoppedByCallback) throw *callbackError;
  return toPython(result);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "OracleMesh core: multi-material tetrahedral meshing of CAD assemblies";
  static py::exception<Error> error(m, "Error");
  static py::exception<InputError> inputError(m, "InputError", error.ptr());
  static py::exception<LimitError> limitError(m, "LimitError", error.ptr());
  static py::exception<Cancelled> cancelled(m, "Cancelled", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      inputError(e.what());
    } catch (const LimitError& e) {
      limitError(e.what());
    } catch (const Cancelled& e) {
      cancelled(e.what());
    } catch (const Error& e) {
      error(e.what());
    }
  });
  m.def("run", &run, py::arg("job_json"), py::arg("base_directory") = "", py::arg("progress") = py::none(),
        "Run a job given as JSON text; returns a dict of numpy arrays and the report as JSON text.");
  m.def("version", &version);
  m.def(
      "step_uncertainty",
      [](const std::string& path) { return declaredStepUncertainty(path, "STEP file '" + path + "'"); },
      py::arg("path"),
      "The largest length uncertainty (UNCERTAINTY_MEASURE_WITH_UNIT) a STEP file declares, in mm; 0 when none.");
  m.def("require_job_file_size", &jobjson::requireJobFileSize, py::arg("path"),
        "InputError when the job file at path is over the size limit (max_job_bytes), before it is read.");
  m.attr("max_job_bytes") = jobjson::kMaxBytes;
  // For oraclemesh.worker, the child of run_isolated, which has a hard deadline of its own.
  m.def("watch_opencascade_in_this_thread", &OpenCascadeWork::watchThisThread,
        "Makes the calling thread (the one that will call run) the one opencascade_stall reports on.");
  m.def(
      "opencascade_stall",
      [](const std::string& jobJson, const std::string& baseDirectory, double timeLimit, double grace,
         const std::string& phase) {
        return openCascadeStallMessage(JobSpec::fromJsonText(jobJson, baseDirectory), timeLimit, grace, phase);
      },
      py::arg("job_json"), py::arg("base_directory"), py::arg("time_limit"), py::arg("grace"), py::arg("phase"),
      "The InputError message when the watched thread is inside OpenCASCADE on one of the job's inputs, else ''.");
  // Test hook of oraclemesh.worker (ORACLEMESH_WORKER_HANG=opencascade:<phase>): blocks the
  // calling thread for good as a call looping inside OpenCASCADE on input `input` would.
  m.def("hang_in_opencascade", [](const std::string& input) {
    const OpenCascadeWork working(input);
    py::gil_scoped_release release;
    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
  });
}
