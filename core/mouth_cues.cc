#include "core/mouth_cues.h"

#include <algorithm>

namespace koma {

MouthShape AnimeShapeOfCue(char shape) {
  switch (shape) {
    case 'A':
    case 'B':
    case 'G':
      return MouthShape::kClosed;
    case 'D':
      return MouthShape::kOpen;
    default:  // C, E, F, H
      return MouthShape::kMid;
  }
}

char CueOfAnimeShape(MouthShape shape) {
  switch (shape) {
    case MouthShape::kClosed:
      return 'A';
    case MouthShape::kMid:
      return 'C';
    case MouthShape::kOpen:
      break;
  }
  return 'D';
}

VoiceActivity CuesOnFrames(const std::vector<MouthCue>& cues, double frame_fps, int frames) {
  VoiceActivity v;
  v.follow.assign(static_cast<size_t>(std::max(frames, 0)), MouthShape::kClosed);
  size_t c = 0;  // the first cue that may still cover a frame: times only grow
  int begin = -1;
  for (int g = 0; g <= frames; ++g) {
    bool speaking = false;
    if (g < frames) {
      const double t = static_cast<double>(g) / frame_fps;
      while (c < cues.size() && cues[c].end_s <= t) ++c;
      if (c < cues.size() && cues[c].start_s <= t && cues[c].shape != 'X') {
        speaking = true;
        v.follow[g] = AnimeShapeOfCue(cues[c].shape);
      }
    }
    if (speaking && begin < 0) begin = g;
    if (!speaking && begin >= 0) {
      v.speech.push_back({begin, g});
      begin = -1;
    }
  }
  return v;
}

std::vector<MouthCue> CuesOfHolds(const std::vector<MouthHold>& holds, double frame_fps,
                                  double duration_s) {
  std::vector<MouthCue> cues;
  const auto time = [frame_fps](int frame) { return static_cast<double>(frame) / frame_fps; };
  int at = 0;  // frame the next cue starts at
  for (const MouthHold& hold : holds) {
    if (hold.begin > at) cues.push_back({time(at), time(hold.begin), 'X'});
    cues.push_back({time(hold.begin), time(hold.begin + hold.length), CueOfAnimeShape(hold.shape)});
    at = hold.begin + hold.length;
  }
  const double end = std::max(duration_s, time(at));
  if (end > time(at) || cues.empty()) cues.push_back({time(at), end, 'X'});
  return cues;
}

}  // namespace koma
