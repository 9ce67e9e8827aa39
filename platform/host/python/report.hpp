// Host-only: the contract's JSON report (plan_report) as plain Python values: dicts,
// lists, floats, ints, strings, None; the 3-vectors of the grasps, the support plane and
// the objects (centroid, box) as numpy float64 arrays of shape (3,).
#pragma once
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

namespace fg::python {
namespace py = pybind11;

//! Any JSON value as the Python value it stands for (no numpy arrays).
py::object to_python(const nlohmann::json& j);

//! A plan report, its 3-vectors as numpy arrays.
py::dict report_to_python(const nlohmann::json& report);

}  // namespace fg::python
