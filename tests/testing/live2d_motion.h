// Generated motions that look like the Live2D motions Cubism animators make (issue 29): 40-80
// parameter curves with Live2D's standard ids, keyed on their own at staggered times (the arm
// 1-4 frames after the shoulder, the hand after the arm, hair a few frames later), Bezier
// eases with settle keys, blinks anywhere and a talking mouth. Their keyframes' union puts a
// key every one or two frames in busy passages, which is what key-pose merging is for.
//
// Deterministic (SplitMix64): the same seed gives the same motion on every machine.
#ifndef KOMA_TESTS_TESTING_LIVE2D_MOTION_H_
#define KOMA_TESTS_TESTING_LIVE2D_MOTION_H_

#include <algorithm>
#include <string>
#include <vector>

#include "core/curves.h"
#include "core/split_mix64.h"

namespace koma::testing {

// Related curves, each following the one before it by 1-4 frames (overlapping action).
inline const std::vector<std::vector<std::string>>& Live2dChains() {
  static const std::vector<std::vector<std::string>> chains = {
      {"ParamBodyAngleX", "ParamAngleX", "ParamEyeBallX", "ParamHairFront", "ParamHairSide"},
      {"ParamBodyAngleY", "ParamAngleY", "ParamEyeBallY", "ParamHairBack"},
      {"ParamBodyAngleZ", "ParamAngleZ", "ParamHairFluffy", "ParamBustX"},
      {"ParamShoulderY", "ParamArmLA", "ParamArmLB", "ParamHandL", "ParamHandLB"},
      {"ParamArmRA", "ParamArmRB", "ParamHandR", "ParamHandRB"},
      {"ParamBrowLY", "ParamBrowRY", "ParamBrowLAngle", "ParamBrowRAngle"},
      {"ParamBrowLForm", "ParamBrowRForm", "ParamBrowLX", "ParamBrowRX"},
      {"ParamEyeLSmile", "ParamEyeRSmile", "ParamMouthForm", "ParamCheek"},
      {"ParamBreath", "ParamBustY", "ParamBaseX", "ParamBaseY"},
  };
  return chains;
}

struct Live2dMotionSpec {
  double fps = 30.0;
  int curve_count = 60;  // 40-80 in the tests; beyond the standard ids, "ParamExtra<k>" chains
  double seconds = 5.0;
  uint64_t seed = 1;
  // Quick accents (issue 40): now and then a body curve flicks out and back within 2 frames of
  // 30 fps (a nod, a hand's snap), a keyed peak no merged key pose stands for.
  bool accents = false;
  // Loops (Live2D Meta.Loop, idle motions): every curve ends on the value it starts with.
  bool loops = false;
};

namespace live2d_motion_internal {

// An integer in [0, n), n >= 1.
inline int Below(SplitMix64& rng, int n) { return rng.Int(0, n - 1); }

// A Cubism-style ease from the previous point to (frame, value): handles at a third and two
// thirds of the time, flat at both ends.
inline CurveSegment Ease(const CurvePoint& from, double frame, double value) {
  CurveSegment s;
  s.type = SegmentType::kBezier;
  const double span = frame - from.frame;
  s.handles[0] = {from.frame + span / 3.0, from.value};
  s.handles[1] = {from.frame + 2.0 * span / 3.0, value};
  s.end = {frame, value};
  return s;
}

inline void AddPoint(Curve& curve, SegmentType type, double frame, double value) {
  const CurvePoint& last = curve.segments.empty() ? curve.start : curve.segments.back().end;
  if (frame <= last.frame) return;  // keys of one curve strictly increase
  if (type == SegmentType::kBezier) {
    curve.segments.push_back(Ease(last, frame, value));
    return;
  }
  CurveSegment s;
  s.type = type;
  s.end = {frame, value};
  curve.segments.push_back(s);
}

inline double LastFrame(const Curve& curve) {
  return curve.segments.empty() ? curve.start.frame : curve.segments.back().end.frame;
}

// Beats (main pose times) every 0.3-1.0 s, in frames.
inline std::vector<int> Beats(SplitMix64& rng, int frame_count, double fps) {
  std::vector<int> beats;
  int t = Below(rng, static_cast<int>(fps / 3)) + 1;
  while (t < frame_count - 1) {
    beats.push_back(t);
    t += static_cast<int>(fps * 0.3 + static_cast<double>(Below(rng, static_cast<int>(fps * 0.7))));
  }
  return beats;
}

// A body/face curve of a chain: eased moves to a new value at each beat + its offset, often
// with a settle key 2-6 frames later (overshoot), sometimes linear.
inline Curve ChainCurve(SplitMix64& rng, const std::string& id, const std::vector<int>& beats,
                        int offset, int frame_count, double fps, bool moving, bool accents) {
  Curve curve;
  curve.id = id;
  curve.start = {0.0, rng.Unit() * 2.0 - 1.0};
  const int scale = fps > 45 ? 2 : 1;  // offsets and settles in 30 fps frames, doubled at 60
  double value = curve.start.value;
  for (int beat : beats) {
    if (!moving) break;
    const int at = beat + offset;
    if (at >= frame_count - 1) break;
    value = rng.Unit() * 2.0 - 1.0;
    const SegmentType type = Below(rng, 5) == 0 ? SegmentType::kLinear : SegmentType::kBezier;
    AddPoint(curve, type, at, value);
    if (Below(rng, 2) == 0) {
      const int settle = at + scale * (2 + Below(rng, 5));
      value += (rng.Unit() - 0.5) * 0.3;
      if (settle < frame_count - 1) AddPoint(curve, SegmentType::kBezier, settle, value);
    }
    if (accents && Below(rng, 3) == 0) {  // out and back within 2 frames (of 30 fps)
      const int out = static_cast<int>(LastFrame(curve)) + scale * (3 + Below(rng, 4));
      const double flick = value + (rng.Unit() < 0.5 ? -1.0 : 1.0) * (0.4 + 0.6 * rng.Unit());
      if (out + 2 * scale < frame_count - 1) {
        AddPoint(curve, SegmentType::kLinear, out, value);
        AddPoint(curve, SegmentType::kBezier, out + scale, flick);
        AddPoint(curve, SegmentType::kBezier, out + 2 * scale, value);
      }
    }
  }
  AddPoint(curve, SegmentType::kLinear, frame_count - 1, value);
  if (curve.segments.empty()) AddPoint(curve, SegmentType::kLinear, frame_count - 1, value);
  return curve;
}

// Blinks anywhere: open (1), shut over 2-3 frames, closed 0-2 frames, open over 3-5 frames;
// the right eye a frame after the left now and then.
inline void AddBlinks(SplitMix64& rng, Curve& left, Curve& right, int frame_count, double fps) {
  const int scale = fps > 45 ? 2 : 1;
  int t = Below(rng, static_cast<int>(fps)) + 2;
  while (t + 12 * scale < frame_count - 1) {
    const int lag = Below(rng, 2) * scale;
    for (Curve* eye : {&left, &right}) {
      const int at = t + (eye == &right ? lag : 0);
      const int shut = at + scale * (2 + Below(rng, 2));
      const int closed_end = shut + scale * Below(rng, 3);
      const int open = closed_end + scale * (3 + Below(rng, 3));
      AddPoint(*eye, SegmentType::kLinear, at, 1.0);
      AddPoint(*eye, SegmentType::kLinear, shut, 0.0);
      AddPoint(*eye, SegmentType::kLinear, closed_end, 0.0);
      AddPoint(*eye, SegmentType::kBezier, open, 1.0);
    }
    t += static_cast<int>(fps * (1.0 + rng.Unit() * 3.0));
  }
}

// Talking: the mouth keyed every 2-4 frames (of 30 fps) through speech stretches.
inline void AddSpeech(SplitMix64& rng, Curve& mouth, int frame_count, double fps) {
  const int scale = fps > 45 ? 2 : 1;
  int t = Below(rng, static_cast<int>(fps / 2)) + 1;
  while (t < frame_count - 1) {
    const int end = std::min(frame_count - 2, t + static_cast<int>(fps * (0.5 + rng.Unit())));
    for (; t < end; t += scale * (2 + Below(rng, 3))) {
      AddPoint(mouth, SegmentType::kBezier, t, rng.Unit());
    }
    AddPoint(mouth, SegmentType::kLinear, t, 0.0);
    t += static_cast<int>(fps * (0.3 + rng.Unit()));
  }
}

}  // namespace live2d_motion_internal

// A motion with spec.curve_count curves (chains of standard ids, then "ParamExtra<k>" chains),
// the eyes blinking and the mouth talking. About one curve in eight never moves.
inline CurveSet Live2dMotion(const Live2dMotionSpec& spec) {
  namespace in = live2d_motion_internal;
  SplitMix64 rng(spec.seed);
  CurveSet set;
  set.fps = spec.fps;
  set.frame_count = static_cast<int>(spec.fps * spec.seconds) + 1;
  set.beziers_restricted = true;
  const int frames = set.frame_count;
  Curve left, right, mouth;
  left.id = "ParamEyeLOpen";
  right.id = "ParamEyeROpen";
  mouth.id = "ParamMouthOpenY";
  left.start = right.start = {0.0, 1.0};
  mouth.start = {0.0, 0.0};
  in::AddBlinks(rng, left, right, frames, spec.fps);
  in::AddSpeech(rng, mouth, frames, spec.fps);
  for (Curve* c : {&left, &right, &mouth}) {
    const double last = c->segments.empty() ? c->start.value : c->segments.back().end.value;
    if (in::LastFrame(*c) < frames - 1) in::AddPoint(*c, SegmentType::kLinear, frames - 1, last);
    set.curves.push_back(std::move(*c));
  }
  const int scale = spec.fps > 45 ? 2 : 1;
  for (int chain = 0; static_cast<int>(set.curves.size()) < spec.curve_count; ++chain) {
    const auto& standard = Live2dChains();
    std::vector<std::string> ids;
    if (chain < static_cast<int>(standard.size())) {
      ids = standard[chain];
    } else {
      for (int k = 0; k < 4; ++k) ids.push_back("ParamExtra" + std::to_string(chain * 4 + k));
    }
    const std::vector<int> beats = in::Beats(rng, frames, spec.fps);
    int offset = 0;
    for (const std::string& id : ids) {
      if (static_cast<int>(set.curves.size()) >= spec.curve_count) break;
      const bool moving = in::Below(rng, 8) != 0;
      set.curves.push_back(
          in::ChainCurve(rng, id, beats, offset, frames, spec.fps, moving, spec.accents));
      offset += scale * (1 + in::Below(rng, 4));  // the next trails by 1-4 frames
    }
  }
  if (spec.loops) {  // the last key returns to the first key's value
    for (Curve& curve : set.curves) {
      CurveSegment& last = curve.segments.back();
      last.end.value = curve.start.value;
      if (last.type == SegmentType::kBezier) last.handles[1].value = curve.start.value;
    }
  }
  return set;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_TESTING_LIVE2D_MOTION_H_
