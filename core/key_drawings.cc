// Every key is drawn: the keys a curve's drawings carry and the time each drawing shows.
#include "core/key_drawings.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace koma {
namespace {

// Which of two keys falling in one drawing it carries: the last key beats every other (the
// loop's end), then the first, then the larger swing; equal swings keep the earlier key `a`.
bool Beats(const KeyDrawing& b, const KeyDrawing& a) {
  const auto rank = [](KeyRole role) {
    return role == KeyRole::kLast ? 2 : role == KeyRole::kFirst ? 1 : 0;
  };
  if (rank(b.role) != rank(a.role)) return rank(b.role) > rank(a.role);
  return b.swing > a.swing;
}

}  // namespace

std::vector<KeyDrawing> KeysToDraw(const Curve& curve) {
  std::vector<KeyDrawing> keys;
  // A dense curve's keys are its samples (a CSV's per-frame values: a peak is a sample); a
  // keyframe curve's are its start (point 0) and each segment's end that a reader did not
  // insert (point s + 1 for segment s): inserted points shape the curve but are no keys.
  std::vector<CurvePoint> dense_points;
  std::vector<size_t> key_points;
  if (curve.dense()) {
    for (size_t f = 0; f < curve.samples.size(); ++f) {
      dense_points.push_back({static_cast<double>(f), curve.samples[f]});
      key_points.push_back(f);
    }
  } else if (!curve.segments.empty()) {
    key_points.push_back(0);
    for (size_t s = 0; s < curve.segments.size(); ++s) {
      if (!curve.segments[s].inserted) key_points.push_back(s + 1);
    }
  }
  if (key_points.size() < 2) return keys;
  const auto point = [&](size_t p) -> const CurvePoint& {
    if (curve.dense()) return dense_points[p];
    return p == 0 ? curve.start : curve.segments[p - 1].end;
  };
  const size_t n = key_points.size();
  const auto value_of = [&](size_t i) { return point(key_points[i]).value; };
  bool moves = false;
  for (size_t i = 1; i < n && !moves; ++i) moves = value_of(i) != value_of(0);
  if (!moves) return keys;  // every drawing shows the one value: nothing to place
  for (size_t i = 0; i < n; ++i) {
    const size_t p = key_points[i];
    // Changes of value from the key before and to the key after (0 at the ends).
    const double in = i > 0 ? value_of(i) - value_of(i - 1) : 0.0;
    const double out = i + 1 < n ? value_of(i + 1) - value_of(i) : 0.0;
    KeyDrawing key;
    key.frame = point(p).frame;
    // What the curve shows at the key's time: its value, but where an inverse-stepped segment
    // starts the value it steps to, which that segment shows from the key on.
    const bool inverse = !curve.dense() && p < curve.segments.size() &&
                         curve.segments[p].type == SegmentType::kInverseStepped;
    key.value = inverse ? curve.segments[p].end.value : point(p).value;
    key.swing = std::max(std::fabs(in), std::fabs(out));
    if (i + 1 == n) {
      key.role = KeyRole::kLast;
    } else if (i == 0) {
      key.role = KeyRole::kFirst;
    } else {
      const bool turns = (in > 0.0 && out < 0.0) || (in < 0.0 && out > 0.0);
      const bool hold_edge = (in == 0.0) != (out == 0.0);
      if (!turns && !hold_edge) continue;
      key.role = KeyRole::kExtreme;
    }
    keys.push_back(key);
  }
  return keys;
}

CurveDrawingTimes PlaceKeysOnDrawings(std::vector<KeyDrawing> keys,
                                      const std::vector<double>& tau) {
  CurveDrawingTimes out;
  const size_t drawings = tau.size();
  out.time = tau;
  out.key.assign(drawings, -1);
  out.at_key.assign(drawings, -1);
  for (size_t k = 0; k < keys.size(); ++k) {
    KeyDrawing& key = keys[k];
    key.drawn = false;
    key.displaced = false;
    if (key.drawing < 0 || static_cast<size_t>(key.drawing) >= drawings) continue;
    int& carried = out.key[static_cast<size_t>(key.drawing)];
    if (carried < 0 || Beats(key, keys[static_cast<size_t>(carried)])) carried = static_cast<int>(k);
  }
  // A key that lost its drawing moves next door when no key of the curve falls there: to the
  // drawing before if it is earlier than the key that won, after if later. Two extremes then
  // show a drawing apart instead of one being lost (a settle 2 frames after a beat, an accent's
  // way out and back). Of several keys that could move into one drawing, the one that Beats the
  // others does. Keys stay in time order on the drawings, so the times shown still never go
  // backwards.
  std::vector<int> moving_in(drawings, -1);
  for (size_t k = 0; k < keys.size(); ++k) {
    const KeyDrawing& key = keys[k];
    if (key.drawing < 0 || static_cast<size_t>(key.drawing) >= drawings) continue;
    const int winner = out.key[static_cast<size_t>(key.drawing)];
    if (winner == static_cast<int>(k)) continue;
    const int target =
        key.frame < keys[static_cast<size_t>(winner)].frame ? key.drawing - 1 : key.drawing + 1;
    if (target < 0 || static_cast<size_t>(target) >= drawings || out.key[target] >= 0) continue;
    int& in = moving_in[static_cast<size_t>(target)];
    if (in < 0 || Beats(key, keys[static_cast<size_t>(in)])) in = static_cast<int>(k);
  }
  for (size_t d = 0; d < drawings; ++d) {
    if (moving_in[d] < 0) continue;
    out.key[d] = moving_in[d];
    KeyDrawing& key = keys[static_cast<size_t>(moving_in[d])];
    key.drawing = static_cast<int>(d);
    key.displaced = true;
  }
  for (size_t d = 0; d < drawings; ++d) {
    if (out.key[d] < 0) continue;
    KeyDrawing& key = keys[static_cast<size_t>(out.key[d])];
    key.drawn = true;
    out.time[d] = key.frame;
    out.at_key[d] = out.key[d];
  }
  // Clamp the other drawings between the carried keys around them. Keys are in time order and
  // lie in drawings in the same order, so the carried times are non-decreasing, and clamping a
  // non-decreasing tau between them keeps the whole sequence non-decreasing.
  int floor_key = -1;       // the last carried key before d
  size_t next_carrier = 0;  // the first drawing at or after d that carries a key
  for (size_t d = 0; d < drawings; ++d) {
    if (out.key[d] >= 0) {
      floor_key = out.key[d];
      continue;
    }
    if (next_carrier <= d) {
      next_carrier = d + 1;
      while (next_carrier < drawings && out.key[next_carrier] < 0) ++next_carrier;
    }
    const int ceiling_key = next_carrier < drawings ? out.key[next_carrier] : -1;
    if (floor_key >= 0 && out.time[d] <= keys[static_cast<size_t>(floor_key)].frame) {
      out.at_key[d] = floor_key;
    } else if (ceiling_key >= 0 && out.time[d] >= keys[static_cast<size_t>(ceiling_key)].frame) {
      out.at_key[d] = ceiling_key;
    }
    if (out.at_key[d] >= 0) out.time[d] = keys[static_cast<size_t>(out.at_key[d])].frame;
  }
  out.keys = std::move(keys);
  return out;
}

}  // namespace koma
