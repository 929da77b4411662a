#pragma once
// Warnings for parameter choices known to be inaccurate (doc/stability.md).
#include <string>
#include <vector>

namespace Marble {

class System;

struct SceneWarning {
  std::string code; ///< short rule name, e.g. "dt_kT_error"
  std::string
      message;       ///< what, the measured number behind the rule, what to do
  double value = 0.; ///< the scene's value
  double limit = 0.; ///< the rule's threshold
};

std::vector<SceneWarning> check_scene(System &sys);

} // namespace Marble
