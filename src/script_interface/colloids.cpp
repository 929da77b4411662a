// Script interface of the colloid machinery (marble.colloids): the colloid
// pair list. The marble coupling itself is a kernel
// (non_bonded_inter[c, s].marble, interactions.cpp).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

namespace ScriptInterface {

using Marble::System;

void bind_colloids(py::class_<System> &cls) {
  cls.def("n_colloid_pairs", [](System &s) -> std::size_t {
#ifdef MARBLE
    s.ensure_lists();
    return s.colloids().n_pairs();
#else
    (void)s;
    return 0;
#endif
  });
}

} // namespace ScriptInterface
