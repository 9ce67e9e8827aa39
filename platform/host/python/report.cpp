#include "report.hpp"

#include <pybind11/numpy.h>

#include <cstdint>
#include <string>

namespace fg::python {
namespace {

py::array_t<double> vec3(const nlohmann::json& j) {
  py::array_t<double> v(3);
  for (size_t i = 0; i < 3; ++i) v.mutable_at(i) = j.at(i).get<double>();
  return v;
}

//! The 3-vectors of one report object (keys that are absent are left alone).
void vectors_to_numpy(const nlohmann::json& report, py::dict& out, const char* object,
                      std::initializer_list<const char*> keys) {
  if (!report.contains(object)) return;
  py::dict sub = out[object].cast<py::dict>();
  for (const char* k : keys)
    if (report[object].contains(k)) sub[k] = vec3(report[object][k]);
}

}  // namespace

py::object to_python(const nlohmann::json& j) {
  using T = nlohmann::json::value_t;
  switch (j.type()) {
    case T::boolean:
      return py::bool_(j.get<bool>());
    case T::number_integer:
      return py::int_(j.get<int64_t>());
    case T::number_unsigned:
      return py::int_(j.get<uint64_t>());
    case T::number_float:
      return py::float_(j.get<double>());
    case T::string:
      return py::str(j.get_ref<const std::string&>());
    case T::array: {
      py::list l;
      for (const auto& e : j) l.append(to_python(e));
      return std::move(l);
    }
    case T::object: {
      py::dict d;
      for (auto it = j.begin(); it != j.end(); ++it) d[py::str(it.key())] = to_python(it.value());
      return std::move(d);
    }
    default:  // null (and the binary and discarded kinds a report never holds)
      return py::none();
  }
}

namespace {
constexpr std::initializer_list<const char*> kGraspVectors = {"position", "approach", "closing", "pregrasp"};

//! The grasp and the ranked grasps (--top) of a report or of one of its objects.
void grasps_to_numpy(const nlohmann::json& report, py::dict& out) {
  vectors_to_numpy(report, out, "grasp", kGraspVectors);
  if (!report.contains("grasps")) return;
  py::list ranked = out["grasps"].cast<py::list>();
  for (size_t i = 0; i < report["grasps"].size(); ++i) {
    py::dict entry = ranked[i].cast<py::dict>();
    for (const char* k : kGraspVectors) entry[k] = vec3(report["grasps"][i][k]);
  }
}
}  // namespace

py::dict report_to_python(const nlohmann::json& report) {
  py::dict out = to_python(report).cast<py::dict>();
  grasps_to_numpy(report, out);
  vectors_to_numpy(report, out, "support_plane", {"normal"});
  if (report.contains("objects")) {  // --objects all: each with its centroid, box and grasps
    py::list objects = out["objects"].cast<py::list>();
    for (size_t i = 0; i < report["objects"].size(); ++i) {
      const nlohmann::json& o = report["objects"][i];
      py::dict entry = objects[i].cast<py::dict>();
      entry["centroid"] = vec3(o["centroid"]);
      vectors_to_numpy(o, entry, "box", {"min", "max"});
      grasps_to_numpy(o, entry);
    }
  }
  return out;
}

}  // namespace fg::python
