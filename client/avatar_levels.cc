#include "client/avatar_levels.h"

#include <algorithm>

namespace koma::client {

AvatarLevels AvatarLevelsOf(const v1::LiveLipBlinkSetup& setup) {
  AvatarLevels levels;
  const v1::MouthSettings& mouth = setup.mouth();
  levels.mouth.min = mouth.has_min() ? mouth.min() : 0.0;
  levels.mouth.max = mouth.has_max() ? mouth.max() : std::max(1.0, levels.mouth.min + 1.0);
  const v1::EyeSettings& eyes = setup.eyes();
  levels.eyes.min = eyes.has_min() ? eyes.min() : 0.0;
  levels.eyes.max = eyes.has_max() ? eyes.max() : 1.0;
  return levels;
}

double Normalised(double level, LevelRange range) {
  if (!(range.max > range.min)) return 0.0;
  const double t = (level - range.min) / (range.max - range.min);
  return std::clamp(t, 0.0, 1.0);
}

double MouthOpenness(const v1::LiveLipBlinkFrame& frame, const AvatarLevels& levels) {
  return Normalised(frame.mouth_level(), levels.mouth);
}

double EyeOpenness(const v1::LiveLipBlinkFrame& frame, const AvatarLevels& levels) {
  return Normalised(frame.eye_level(), levels.eyes);
}

}  // namespace koma::client
