// Script interface of the DPD analysis: the DPD part of the pressure tensor
// (core: analysis/dpd_stress.cpp; convention: doc/dpd.md).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"
#include "utils/errors.hpp"

#include <pybind11/numpy.h>

#include <algorithm>
#include <array>

namespace ScriptInterface {


void bind_dpd(py::class_<Marble::System> &cls) {
  cls.def("dpd_stress", [](Marble::System &s) {
#ifdef DPD
    auto const st = s.dpd_stress();
    std::array<double, 9> tot{};
    for (int k = 0; k < 9; ++k)
      tot[k] = st.friction[k] + st.noise[k];
    py::dict d;
    d["total"] = mat_to_array(tot);
    d["friction"] = mat_to_array(st.friction);
    d["noise"] = mat_to_array(st.noise);
    return d;
#else
    (void)s;
    throw Utils::FeaturesError("DPD", "analysis.dpd_stress");
#endif
  });
}

} // namespace ScriptInterface
