// The 0..1 values avatar apps take from a LiveLipBlink frame: VRM blend shape clips over VMC
// (0 neutral, 1 full) and VTube Studio's MouthOpen and EyeOpenLeft/Right inputs (0 closed,
// 1 open). A frame carries the levels the stream's setup chose (MouthSettings and EyeSettings
// min, mid, max); each is mapped linearly from [min, max] to [0, 1], so the three drawings
// stay three distinct steps: closed 0, mid mid_ratio, open 1 (docs/live.md).
#ifndef KOMA_CLIENT_AVATAR_LEVELS_H_
#define KOMA_CLIENT_AVATAR_LEVELS_H_

#include "koma/v1/retime.pb.h"

namespace koma::client {

// The closed and open levels of one curve, as the setup asked for them.
struct LevelRange {
  double min = 0.0;
  double max = 1.0;
};

struct AvatarLevels {
  LevelRange mouth;  // MouthSettings min / max
  LevelRange eyes;   // EyeSettings min / max
};

// The levels the server uses for `setup` (retime.proto, LiveLipBlinkSetup): mouth min unset 0,
// max unset max(1, min + 1); eyes min unset 0, max unset 1.
AvatarLevels AvatarLevelsOf(const v1::LiveLipBlinkSetup& setup);

// (level - min) / (max - min) clamped to [0, 1]; 0 when max <= min (no range to map).
double Normalised(double level, LevelRange range);

// How open the mouth is, 0 (MOUTH_CLOSED) .. 1 (MOUTH_OPEN).
double MouthOpenness(const v1::LiveLipBlinkFrame& frame, const AvatarLevels& levels);
// How open the eyes are, 0 (shut: an auto-blink's closed frame) .. 1 (open).
double EyeOpenness(const v1::LiveLipBlinkFrame& frame, const AvatarLevels& levels);

}  // namespace koma::client

#endif  // KOMA_CLIENT_AVATAR_LEVELS_H_
