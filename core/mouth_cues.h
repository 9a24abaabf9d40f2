// Rhubarb Lip Sync's mouth cues <-> koma's three anime drawings (docs/semantics.md, "Mouth
// cues"). Rhubarb names nine mouths A-H and X (rest); anime draws three. Going in, each letter
// maps to the drawing nearest its openness and the cues are sampled on the film grid; going
// out, each mouth hold becomes one cue and every stretch outside speech an X.
#ifndef KOMA_CORE_MOUTH_CUES_H_
#define KOMA_CORE_MOUTH_CUES_H_

#include <vector>

#include "core/lip_blink.h"
#include "core/voice_activity.h"

namespace koma {

struct MouthCue {
  double start_s = 0.0;  // seconds
  double end_s = 0.0;    // seconds, > start_s
  char shape = 'X';      // 'A'..'H' or 'X'
};

// A, B, G (lips shut or teeth together) -> closed; C, E, F, H (open vowels, rounded lips,
// tongue) -> mid; D (wide open) -> open; X (rest) is silence, not a drawing (callers test it
// first). Requires a valid letter.
MouthShape AnimeShapeOfCue(char shape);

// The letter a drawing is written as: closed A, mid C, open D (silence is X).
char CueOfAnimeShape(MouthShape shape);

// Cues (sorted by start, not overlapping) sampled at frames 0 .. frames - 1 of `frame_fps`:
// frame g shows the cue in force at its time g / frame_fps (start <= t < end); speech is the
// maximal runs of frames showing a letter other than X, and `follow` their drawings (closed
// elsewhere). The loudness fields are left at their defaults.
VoiceActivity CuesOnFrames(const std::vector<MouthCue>& cues, double frame_fps, int frames);

// Mouth holds (frames at `frame_fps`, in time order, inside `speech`) as cues covering
// [0, duration_s]: one per hold, X for every stretch outside them. Times are frame /
// frame_fps; the last cue ends at max(duration_s, the last hold's end).
std::vector<MouthCue> CuesOfHolds(const std::vector<MouthHold>& holds, double frame_fps,
                                  double duration_s);

}  // namespace koma

#endif  // KOMA_CORE_MOUTH_CUES_H_
