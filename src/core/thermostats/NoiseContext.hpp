#pragma once
// What a force kernel needs to draw the counter-based thermostat noise of
// this step (utils/noise.hpp): whether the thermostat acts, its seed and the
// step counter. Filled by System::noise_context().
#include <cstdint>

namespace Marble {

struct NoiseContext {
  bool on = false;
  std::uint64_t seed = 0, counter = 0;
};

} // namespace Marble
