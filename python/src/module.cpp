// pdmesh._core: the Python extension over the same C++ library as the `pdmesh` command. The core's
// typed errors become the exceptions of pdmesh.errors with the command's messages.
#include <exception>

#include "bindings.hpp"
#include "core/errors.hpp"

namespace pdmesh::py {

nb::object errors_module() { return nb::module_::import_("pdmesh.errors"); }

namespace {

void raise(const char* type, const std::exception& e) {
  // The translator runs with the GIL held; importing can fail only if the package is broken.
  try {
    nb::object cls = errors_module().attr(type);
    PyErr_SetString(cls.ptr(), e.what());
  } catch (const nb::python_error& failed) {
    nb::python_error(failed).restore();
  }
}

// Most specific first: GeometryError and LimitError are InputErrors, InputError is an Error.
void translate(const std::exception_ptr& p, void*) {
  try {
    std::rethrow_exception(p);
  } catch (const GeometryError& e) {
    raise("GeometryError", e);
  } catch (const LimitError& e) {
    raise("LimitError", e);
  } catch (const InputError& e) {
    raise("InputError", e);
  } catch (const DeviceError& e) {
    raise("DeviceError", e);
  } catch (const SimulationError& e) {
    raise("SimulationError", e);
  } catch (const Error& e) {
    raise("Error", e);
  }
}

}  // namespace

}  // namespace pdmesh::py

NB_MODULE(_core, m) {
  using namespace pdmesh::py;
  m.doc() = "pdmesh's C++ core (use the pdmesh package, not this module, directly)";
  m.attr("version") = PDMESH_VERSION;
  nb::register_exception_translator(translate);
  bind_config(m);
  bind_mesher(m);
  bind_mesh(m);
  bind_cli(m);
  bind_motion(m);
  bind_stepper(m);
}
