#pragma once
// Shared by the translation units of axonguide._core (docs/guide.md §2).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <future>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/support/error.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg::py_api {

namespace py = pybind11;

// An InputError raised while reading a scene: Python's axonguide.SceneError. Every other
// InputError is axonguide.InputError (its base, a ValueError).
class SceneInputError : public InputError {
 public:
  explicit SceneInputError(const InputError& e) : InputError(e.what(), e.key(), e.value(), e.allowed()) {}
};

// Text that may hold a file name as the file system has it (any bytes): decoded as Python
// decodes names (surrogateescape), so a name that is not UTF-8 is a str, not an error.
inline py::str fs_text(const std::string& text) {
  PyObject* s = PyUnicode_DecodeFSDefaultAndSize(text.data(), static_cast<Py_ssize_t>(text.size()));
  if (!s) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(s);
}

inline py::list fs_texts(const std::vector<std::string>& texts) {
  py::list out;
  for (const std::string& t : texts) out.append(fs_text(t));
  return out;
}

// Whether the caller is Python's main thread (the only one that runs signal handlers).
inline bool on_python_main_thread() {
  const py::module_ threading = py::module_::import("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}

// Runs `work` on a thread of its own while this one, the GIL released, polls Python's signal
// handlers every 0.1 s (when it is the main thread): a handler's exception (KeyboardInterrupt
// for SIGINT) sets `stop`, which the work's runs read between steps, and is raised once the
// work has ended. Sweeps and fits run their members on TBB's threads, where Python's
// handlers cannot run; this is how Ctrl-C reaches them.
template <class Work>
auto interruptible(std::atomic<bool>& stop, Work&& work) -> decltype(work()) {
  const bool main = on_python_main_thread();
  std::optional<py::error_already_set> signalled;
  auto task = std::async(std::launch::async, std::forward<Work>(work));
  {
    py::gil_scoped_release release;
    while (task.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
      if (!main || signalled) continue;
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) {
        signalled.emplace();  // fetches (and clears) the handler's exception
        stop = true;
      }
    }
  }
  if (signalled) {
    try {
      task.get();  // Interrupted, or whatever the work ended with first
    } catch (...) {
    }
    throw *signalled;
  }
  return task.get();
}

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
