// Script interface of the DPD analysis: the DPD part of the pressure tensor
// (core: analysis/dpd_stress.cpp; convention: doc/dpd.md).
#include "script_interface/bindings.hpp"
#include "utils/errors.hpp"

#include <pybind11/numpy.h>

#include <algorithm>
#include <array>

namespace ScriptInterface {

namespace {
py::array_t<double> mat3(std::array<double, 9> const &m) {
  py::array_t<double> a({3, 3});
  std::copy(m.begin(), m.end(), a.mutable_data());
  return a;
}
} // namespace

void bind_dpd(py::class_<Marble::System> &cls) {
  cls.def("dpd_stress", [](Marble::System &s) {
#ifdef DPD
    auto const st = s.dpd_stress();
    std::array<double, 9> tot{};
    for (int k = 0; k < 9; ++k)
      tot[k] = st.friction[k] + st.noise[k];
    py::dict d;
    d["total"] = mat3(tot);
    d["friction"] = mat3(st.friction);
    d["noise"] = mat3(st.noise);
    return d;
#else
    (void)s;
    throw Utils::FeaturesError("DPD", "analysis.dpd_stress");
#endif
  });
}

} // namespace ScriptInterface
