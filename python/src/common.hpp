#pragma once
// Shared by the translation units of axonguide._core (docs/methods.md §13).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/error.hpp"
#include "axonguide/run.hpp"
#include "axonguide/scene.hpp"

namespace axg::py_api {

namespace py = pybind11;

// An InputError raised while reading a scene: Python's axonguide.SceneError. Every other
// InputError is axonguide.InputError (its base, a ValueError).
class SceneInputError : public InputError {
 public:
  explicit SceneInputError(const InputError& e) : InputError(e.what(), e.key(), e.value(), e.allowed()) {}
};

// A parsed scene and what parsing it said.
struct SceneHandle {
  Scene scene;
  std::vector<std::string> warnings;
  std::string origin;
};

// A finished run, as `axonguide run` holds it before write_outputs.
struct RunHandle {
  RunResult result;
  std::vector<std::string> warnings;
  std::string backend;
  int threads = 1;
};

// Scene parsing whose InputError becomes SceneError.
SceneHandle scene_from_text(const std::string& text, const std::string& origin);

// backend by name and a thread count, checked as the command line checks them.
RunOptions run_options(const std::string& backend);
int checked_threads(int threads);

py::object json_to_py(const nlohmann::json& j);

// A read-only NumPy view of `count` rows of `row_bytes` doubles... owned by `base`.
template <class T>
py::array_t<T> readonly_view(const T* data, std::vector<py::ssize_t> shape, py::handle base) {
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t stride = sizeof(T);
  for (std::size_t k = shape.size(); k-- > 0;) {
    strides[k] = stride;
    stride *= shape[k];
  }
  py::array_t<T> a(shape, strides, data, base);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

void bind_study(py::module_& m);

}  // namespace axg::py_api
