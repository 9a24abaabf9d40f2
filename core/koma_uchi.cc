// RetimeCurves: key poses, per-segment parameters, timings (frames -> drawings -> source
// times) and the curves sampled at those times. Holds and spacing live in spacing.cc, the
// options' validation in koma_uchi_options.cc.
#include "core/koma_uchi.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>

#include "core/curve_cursor.h"
#include "core/film_grid.h"
#include "core/key_drawings.h"
#include "core/stop_check.h"

namespace koma {
namespace {

// The n, s_a and s_b of one segment between key poses.
struct SegmentParams {
  int frames_per_drawing = 3;
  double tame = 1.0;
  double tsume = 1.0;
};

// The options' defaults with the segment overrides applied.
std::vector<SegmentParams> DefaultSegmentParams(const KomaUchiOptions& options,
                                                size_t segment_count) {
  std::vector<SegmentParams> params(segment_count,
                                    {options.frames_per_drawing, options.tame, options.tsume});
  for (const SegmentOverride& o : options.segment_overrides) {
    SegmentParams& p = params[static_cast<size_t>(o.segment)];
    p.frames_per_drawing = o.frames_per_drawing.value_or(p.frames_per_drawing);
    p.tame = o.tame.value_or(p.tame);
    p.tsume = o.tsume.value_or(p.tsume);
  }
  return params;
}

// Drawings of one segment [keys[x], keys[x + 1]]: each starts where the previous one's hold
// ends, the first exactly on the key, and samples tau_j = T_x + (T_{x+1} - T_x) * E_j, where T
// are the key poses' own times in source frames (`key_time`, `next_key_time`): with a grid the
// holds are laid out on grid frames, but a key pose snapped to a grid frame still shows the
// curves at its own time, not the grid frame's.
// Between merged key poses a segment gets floor(L / n) drawings (none shorter than n), between
// named ones ceil(L / n) (none longer than n).
void AppendSegment(int key, int next_key, double key_time, double next_key_time,
                   const SegmentParams& params, bool merged_poses, DrawingTiming& timing) {
  const int length = next_key - key;
  const std::vector<int> holds = merged_poses ? PoseHoldLengths(length, params.frames_per_drawing)
                                              : HoldLengths(length, params.frames_per_drawing);
  const std::vector<double> spacing =
      Spacing(static_cast<int>(holds.size()), params.tame, params.tsume);
  int frame = key;
  for (size_t j = 0; j < holds.size(); ++j) {
    const int drawing = static_cast<int>(timing.drawing_start.size());
    // In source frames, in [key_time, next_key_time]. Without a grid the times are the keys
    // themselves, and this is key + length * E_j bit for bit.
    const double tau = key_time + (next_key_time - key_time) * spacing[j];
    timing.drawing_start.push_back(frame);
    timing.drawing_tau.push_back(tau);
    for (int k = 0; k < holds[j]; ++k, ++frame) {
      timing.drawing_of_frame[frame] = drawing;
      timing.source_frame[frame] = tau;
    }
  }
}

// `keys`: the key poses on the frames the holds are counted in (grid frames with a grid);
// `key_times`: the same key poses' own times in source frames.
DrawingTiming BuildTiming(const std::vector<int>& keys, const std::vector<double>& key_times,
                          const std::vector<SegmentParams>& params, int frames_per_drawing,
                          bool merged_poses) {
  const int frame_count = keys.back() + 1;
  DrawingTiming timing;
  timing.frames_per_drawing = frames_per_drawing;
  timing.drawing_of_frame.resize(static_cast<size_t>(frame_count));
  timing.source_frame.resize(static_cast<size_t>(frame_count));
  for (size_t x = 0; x < params.size(); ++x) {
    AppendSegment(keys[x], keys[x + 1], key_times[x], key_times[x + 1], params[x], merged_poses,
                  timing);
  }
  // The last key pose is a drawing of its own, held for its one frame, showing the clip's end.
  const int last = frame_count - 1;
  timing.drawing_of_frame[last] = static_cast<int>(timing.drawing_start.size());
  timing.source_frame[last] = key_times.back();
  timing.drawing_start.push_back(last);
  timing.drawing_tau.push_back(key_times.back());
  return timing;
}

// A given timing on the counted frames: a drawing per run of equal taus.
DrawingTiming BuildGivenTiming(const std::vector<double>& taus, int frames_per_drawing) {
  DrawingTiming timing;
  timing.frames_per_drawing = frames_per_drawing;
  timing.given = true;
  timing.source_frame = taus;
  timing.drawing_of_frame.resize(taus.size());
  for (size_t g = 0; g < taus.size(); ++g) {
    if (g == 0 || taus[g] != taus[g - 1]) {
      timing.drawing_start.push_back(static_cast<int>(g));
      timing.drawing_tau.push_back(taus[g]);
    }
    timing.drawing_of_frame[g] = static_cast<int>(timing.drawing_start.size()) - 1;
  }
  return timing;
}

// A timing built on grid frames, at the source rate: source frame k shows the drawing of the
// grid frame its time falls in; drawing starts become (fractional) source frames. Taus are
// source frames already.
DrawingTiming ExpandToSource(const DrawingTiming& on_grid, const FilmGrid& grid, int frame_count) {
  DrawingTiming out;
  out.frames_per_drawing = on_grid.frames_per_drawing;
  out.given = on_grid.given;
  const int last_grid = static_cast<int>(on_grid.drawing_of_frame.size()) - 1;
  out.drawing_of_frame.resize(static_cast<size_t>(frame_count));
  out.source_frame.resize(static_cast<size_t>(frame_count));
  for (int k = 0; k < frame_count; ++k) {
    const int g = std::min(grid.GridFrameOf(k), last_grid);
    out.drawing_of_frame[k] = on_grid.drawing_of_frame[g];
    out.source_frame[k] = on_grid.source_frame[g];
  }
  out.drawing_start_grid = on_grid.drawing_start;
  for (int g : on_grid.drawing_start) {
    out.drawing_start.push_back(std::min(grid.FirstSourceFrameAtOrAfter(g), frame_count - 1));
    out.drawing_time.push_back(grid.SourceTime(g));
    out.drawing_tau.push_back(on_grid.source_frame[g]);
  }
  return out;
}

// A hash of what SameCurveTimes compares (equal times, equal hashes).
uint64_t CurveTimesHash(const Curve& curve) {
  uint64_t hash = curve.segments.size();
  const auto mix = [&hash](double x) {
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    if (x == 0.0) bits = 0;  // -0 == 0
    hash = (hash ^ bits) * 0x100000001b3ULL;
    hash ^= hash >> 29;
  };
  mix(curve.start.frame);
  for (const CurveSegment& segment : curve.segments) {
    mix(static_cast<double>(segment.type));
    mix(segment.end.frame);
    if (segment.type == SegmentType::kBezier) {
      mix(segment.handles[0].frame);
      mix(segment.handles[1].frame);
    }
  }
  return hash;
}

// The key poses' own times in source frames, for `pose_frames` (the key poses in source
// frames). On a grid, with the poses made from the keyframes: the earliest keyframe time of the
// group's curves that rounds to the pose's frame (a key at 3.75 frames, an exact grid time,
// shows 3.75, not 4: so a stepped answer read back and retimed shows its own drawings), the
// clip's first and last frame as they are. Otherwise (named key poses, or no grid) the frames.
std::vector<double> PoseTimes(const CurveSet& set, const std::vector<int>& members,
                              const KomaUchiOptions& options, bool on_grid,
                              const std::vector<int>& pose_frames) {
  std::vector<double> times(pose_frames.begin(), pose_frames.end());
  if (!on_grid || !options.key_frames.empty()) return times;
  const int last = set.frame_count - 1;
  std::vector<double> earliest(static_cast<size_t>(set.frame_count), HUGE_VAL);
  const auto note = [&](double t) {
    if (!std::isfinite(t)) return;
    const double f = std::clamp(std::round(t), 0.0, static_cast<double>(last));
    double& e = earliest[static_cast<size_t>(f)];
    e = std::min(e, std::clamp(t, 0.0, static_cast<double>(last)));
  };
  for (int c : members) {
    const Curve& curve = set.curves[static_cast<size_t>(c)];
    if (curve.dense()) continue;
    note(curve.start.frame);
    for (const CurveSegment& segment : curve.segments) {
      if (!segment.inserted) note(segment.end.frame);
    }
  }
  for (size_t x = 0; x < pose_frames.size(); ++x) {
    const int f = pose_frames[x];
    if (f == 0 || f == last) continue;  // the clip's ends
    if (std::isfinite(earliest[static_cast<size_t>(f)]))
      times[x] = earliest[static_cast<size_t>(f)];
  }
  return times;
}

std::map<int, int> HoldHistogram(const DrawingTiming& timing) {
  std::map<int, int> histogram;
  const std::vector<int>& starts = timing.drawing_start;
  const int frame_count = static_cast<int>(timing.drawing_of_frame.size());
  for (size_t d = 0; d < starts.size(); ++d) {
    const int end = d + 1 < starts.size() ? starts[d + 1] : frame_count;
    ++histogram[end - starts[d]];
  }
  return histogram;
}

// The Bezier parameters of curves with the same times at the drawings' taus
// (CurveCursor::EvaluateSharing), per drawing, solved by the first curve that shows that
// drawing at its tau (a curve whose key moved a drawing off its tau solves nothing there).
struct SharedParameters {
  std::vector<double> parameter;
  std::vector<char> solved;
};

// The drawing whose hold contains a key at `frame` (source frames): on the grid, the drawing of
// the grid frame the key snaps to (nearest, ties to the earlier, at most the last); else the
// drawing of the source frame nearest the key.
int DrawingOfKey(const DrawingTiming& timing, const std::optional<FilmGrid>& grid, double frame) {
  if (grid) {
    const std::vector<int>& starts = timing.drawing_start_grid;
    const int g = std::min(grid->NearestGridFrame(frame), starts.back());
    return static_cast<int>(std::upper_bound(starts.begin(), starts.end(), g) - starts.begin()) - 1;
  }
  const double last = static_cast<double>(timing.drawing_of_frame.size() - 1);
  return timing.drawing_of_frame[static_cast<size_t>(std::clamp(std::round(frame), 0.0, last))];
}

// The curve shown once per drawing and held over the drawing's frames: at its tau, except
// where the curve's own keys are drawn (core/key_drawings.h): a drawing that carries a key
// shows its value exactly, one clamped onto a carried key shows that key. The times shown are
// non-decreasing, so the cursor only walks forward.
// `tau`: DrawingTaus(timing).
// exact_taus: no key is drawn (a given timing's GivenGroupTiming::exact_taus).
RetimedCurve RetimeOne(const Curve& curve, bool beziers_restricted, const DrawingTiming& timing,
                       const std::vector<double>& tau, const std::optional<FilmGrid>& grid,
                       int timing_index, const std::map<int, int>& histogram,
                       SharedParameters& shared, bool exact_taus) {
  RetimedCurve out;
  out.timing = timing_index;
  out.hold_histogram = histogram;
  const std::vector<int>& starts = timing.drawing_start;
  const size_t drawings = starts.size();
  const size_t frame_count = timing.drawing_of_frame.size();
  out.values.resize(frame_count);
  out.steps.reserve(drawings);
  const bool on_grid = !timing.drawing_time.empty();
  std::vector<KeyDrawing> keys = exact_taus ? std::vector<KeyDrawing>() : KeysToDraw(curve);
  for (KeyDrawing& key : keys) key.drawing = DrawingOfKey(timing, grid, key.frame);
  CurveDrawingTimes placed = PlaceKeysOnDrawings(std::move(keys), tau);
  if (shared.solved.size() != drawings) {
    shared.parameter.assign(drawings, 0.0);
    shared.solved.assign(drawings, 0);
  }
  CurveCursor cursor(curve, beziers_restricted);
  for (size_t d = 0; d < drawings; ++d) {
    const size_t begin = static_cast<size_t>(starts[d]);
    size_t end = d + 1 < drawings ? static_cast<size_t>(starts[d + 1]) : frame_count;
    if (end < begin) end = begin;  // a grid drawing no source frame shows
    double value;
    if (placed.at_key[d] >= 0) {
      value = placed.keys[static_cast<size_t>(placed.at_key[d])].value;
    } else {
      value = cursor.EvaluateSharing(tau[d], shared.parameter[d], shared.solved[d] != 0);
      shared.solved[d] = 1;
    }
    std::fill(out.values.begin() + begin, out.values.begin() + end, value);
    out.steps.push_back({on_grid ? timing.drawing_time[d] : static_cast<double>(begin), value});
  }
  const double last = static_cast<double>(frame_count - 1);
  if (on_grid && out.steps.back().frame < last) out.steps.push_back({last, out.steps.back().value});
  out.keys = std::move(placed.keys);
  return out;
}

}  // namespace

std::vector<double> DrawingTaus(const DrawingTiming& timing) {
  if (timing.drawing_tau.size() == timing.drawing_start.size()) return timing.drawing_tau;
  std::vector<double> tau;  // a timing without them (read from a response)
  tau.reserve(timing.drawing_start.size());
  for (int start : timing.drawing_start)
    tau.push_back(timing.source_frame[static_cast<size_t>(start)]);
  return tau;
}

std::vector<int> KeyPoses(const KomaUchiOptions& options, const CurveSet& set,
                          const std::vector<int>* members) {
  const int last = set.frame_count - 1;
  // One mark per frame rather than a sort: O(frame_count + keyframes), already unique.
  std::vector<bool> is_key(static_cast<size_t>(set.frame_count), false);
  is_key[0] = true;
  is_key[last] = true;
  for (int key : options.key_frames) {
    if (key >= 0 && key <= last) is_key[key] = true;  // valid options have no others
  }
  // Nearest frame (halves away from zero: std::round is exact), clamped into [0, last].
  const auto mark_time = [&is_key, last](double frame) {
    if (!std::isfinite(frame)) return;  // only in an invalid set
    is_key[static_cast<size_t>(std::clamp(std::round(frame), 0.0, static_cast<double>(last)))] =
        true;
  };
  const auto mark_curve = [&mark_time](const Curve& curve) {
    if (curve.dense()) return;
    mark_time(curve.start.frame);
    for (const CurveSegment& segment : curve.segments) {
      if (!segment.inserted) mark_time(segment.end.frame);  // an inserted point is no key
    }
  };
  if (options.key_frames.empty()) {
    if (members == nullptr) {
      for (const Curve& curve : set.curves) mark_curve(curve);
    } else {
      for (int c : *members) mark_curve(set.curves[static_cast<size_t>(c)]);
    }
  }
  std::vector<int> keys;
  for (int f = 0; f <= last; ++f) {
    if (is_key[f]) keys.push_back(f);
  }
  return keys;
}

bool MergesKeyPoses(const KomaUchiOptions& options) {
  return options.merge_key_poses && options.key_frames.empty();
}

GridKeyPoses KeyPosesOnGrid(const KomaUchiOptions& options, const CurveSet& set,
                            const std::vector<int>* members) {
  GridKeyPoses out;
  const std::vector<int> keys = KeyPoses(options, set, members);
  const std::optional<FilmGrid> grid = FilmGrid::Make(set.fps, options.timing_fps);
  const int last_grid = grid ? grid->GridFrameCount(set.frame_count) - 1 : keys.back();
  // A key pose's frame on the timing's frames: its nearest grid frame, or itself.
  const auto frame_of = [&grid, last_grid](int key) {
    return grid ? std::min(grid->NearestGridFrame(key), last_grid) : key;
  };
  if (!MergesKeyPoses(options)) {
    if (!grid) {
      out.source = keys;
      out.grid = keys;
      return out;
    }
    for (size_t i = 0; i + 1 < keys.size(); ++i) {
      const int g = frame_of(keys[i]);
      if (g >= last_grid || (!out.grid.empty() && g <= out.grid.back())) continue;
      out.source.push_back(keys[i]);
      out.grid.push_back(g);
    }
    out.source.push_back(keys.back());  // the clip's last frame: the last grid frame
    out.grid.push_back(last_grid);
    return out;
  }
  // Merged poses: a keyframe time less than n frames after the pose before it joins that pose
  // (which keeps its time, the earliest), one less than n frames before the clip's end joins
  // the last frame's pose. So consecutive poses are at least n frames apart.
  const int n = options.frames_per_drawing;
  int joining_end = 0;  // keyframe times that joined the clip's last frame
  for (size_t i = 0; i + 1 < keys.size(); ++i) {
    const int g = frame_of(keys[i]);
    if (!out.grid.empty() && g - out.grid.back() < n) {
      ++out.merged.back();
    } else if (!out.grid.empty() && last_grid - g < n) {
      ++joining_end;
    } else {
      out.source.push_back(keys[i]);
      out.grid.push_back(g);
      out.merged.push_back(1);
    }
  }
  out.source.push_back(keys.back());
  out.grid.push_back(last_grid);
  out.merged.push_back(1 + joining_end);
  return out;
}

KomaUchiOptions GroupOptions(const KomaUchiOptions& options, const CurveTimingGroup& group) {
  KomaUchiOptions out;
  out.key_frames = group.key_frames;
  out.merge_key_poses = options.merge_key_poses;
  out.frames_per_drawing = group.frames_per_drawing.value_or(options.frames_per_drawing);
  out.tame = group.tame.value_or(options.tame);
  out.tsume = group.tsume.value_or(options.tsume);
  out.curve_frames_per_drawing = options.curve_frames_per_drawing;
  out.timing_fps = options.timing_fps;
  out.given = options.given;
  return out;  // segment overrides are the default group's
}

std::vector<std::vector<int>> GroupMembers(const KomaUchiOptions& options, const CurveSet& set) {
  std::vector<std::vector<int>> members(options.groups.size() + 1);
  for (size_t c = 0; c < set.curves.size(); ++c) {
    members[static_cast<size_t>(GroupOf(options.groups, set.curves[c].id))].push_back(
        static_cast<int>(c));
  }
  return members;
}

namespace {

// One group's key poses, timings (appended to result.timings) and curves (into their slots of
// result.curves). `options` are the group's own (GroupOptions, or the request's for the
// default group).
TimingGroupResult RetimeGroup(const CurveSet& set, const std::vector<int>& members,
                              const KomaUchiOptions& options, bool keep,
                              const std::string& group_name, KomaUchiResult& result) {
  TimingGroupResult group;
  group.curves = members;
  group.frames_per_drawing = options.frames_per_drawing;
  group.timing = -1;
  if (keep) {  // no key poses, no timing: each curve as it came in
    group.frames_per_drawing = 0;
    for (int c : members) {
      RetimedCurve& out = result.curves[c];
      out.timing = -1;
      out.values = SampleEveryFrame(set.curves[c], set.frame_count, set.beziers_restricted);
    }
    return group;
  }
  const std::optional<FilmGrid> grid = FilmGrid::Make(set.fps, options.timing_fps);
  GridKeyPoses key_poses = KeyPosesOnGrid(options, set, &members);
  group.key_frames = std::move(key_poses.source);
  group.key_merged = std::move(key_poses.merged);
  if (grid) group.key_grid_frames = key_poses.grid;
  const bool merged_poses = MergesKeyPoses(options);
  // A named group no curve matched has key poses but no timing (an answer with no curve in
  // named groups then has exactly the timings of one without groups).
  if (members.empty() && !result.timings.empty()) return group;
  // The keys the timings are built on: grid frames with a grid, else source frames.
  const std::vector<int>& keys = grid ? key_poses.grid : group.key_frames;
  const std::vector<SegmentParams> defaults = DefaultSegmentParams(options, keys.size() - 1);
  const int first_timing = static_cast<int>(result.timings.size());
  group.timing = first_timing;
  const auto given = options.given.find(group_name);
  const bool is_given = given != options.given.end();
  if (is_given) {
    result.timings.push_back(BuildGivenTiming(given->second.taus, options.frames_per_drawing));
  } else {
    const std::vector<double> pose_times =
        PoseTimes(set, members, options, grid.has_value(), group.key_frames);
    result.timings.push_back(
        BuildTiming(keys, pose_times, defaults, options.frames_per_drawing, merged_poses));
  }
  // Each distinct per-curve n (ascending) of the group's curves gets a timing with that n in
  // every segment (the segments' tame and tsume still apply), unless that is the group's first
  // timing itself: n is the default and no segment override changes it.
  std::set<int> curve_ns;
  for (int c : is_given ? std::vector<int>() : members) {
    const auto own = options.curve_frames_per_drawing.find(set.curves[c].id);
    if (own != options.curve_frames_per_drawing.end()) curve_ns.insert(own->second);
  }
  std::map<int, int> timing_of_n;
  for (int n : curve_ns) {
    std::vector<SegmentParams> params = defaults;
    bool same_as_default = n == options.frames_per_drawing;
    for (SegmentParams& p : params) {
      same_as_default = same_as_default && p.frames_per_drawing == n;
      p.frames_per_drawing = n;
    }
    if (same_as_default) {
      timing_of_n[n] = first_timing;
      continue;
    }
    timing_of_n[n] = static_cast<int>(result.timings.size());
    result.timings.push_back(BuildTiming(
        keys, PoseTimes(set, members, options, grid.has_value(), group.key_frames), params, n,
        merged_poses));
  }
  std::map<int, std::map<int, int>> histograms;  // per timing index; on grid frames with a grid
  std::map<int, std::vector<double>> taus;       // per timing index: DrawingTaus
  for (size_t t = static_cast<size_t>(first_timing); t < result.timings.size(); ++t) {
    histograms[static_cast<int>(t)] = HoldHistogram(result.timings[t]);
    if (grid) result.timings[t] = ExpandToSource(result.timings[t], *grid, set.frame_count);
    taus[static_cast<int>(t)] = DrawingTaus(result.timings[t]);
  }
  // Curves with the same times on the same timing share their Bezier parameters at the
  // drawings' taus: solved once (bisection, ~55 cubic evaluations each) for all of them, since
  // the solve depends only on the times. A Spine skeleton's bones are mostly keyed at the same
  // times (the 50-bone benchmark: 150 curves, one set of times). Per timing and hash of the
  // times: the first curve with those times and its parameters.
  std::map<std::pair<int, uint64_t>, std::vector<std::pair<int, SharedParameters>>> solved;
  StopPoll stop(/*steps_between_checks=*/1 << 14);  // segments: a check every ~1 ms
  for (int c : members) {
    const Curve& curve = set.curves[c];
    // Stopped: the rest stay empty; the caller that installed the signal discards the result.
    if (stop.Stop(static_cast<int64_t>(curve.segments.size()) + 1)) break;
    const auto own = options.curve_frames_per_drawing.find(curve.id);
    const int t = is_given || own == options.curve_frames_per_drawing.end()
                      ? first_timing
                      : timing_of_n[own->second];
    SharedParameters own_parameters;
    SharedParameters* parameters = &own_parameters;
    if (!curve.dense() && !set.beziers_restricted) {
      std::vector<std::pair<int, SharedParameters>>& same_hash = solved[{t, CurveTimesHash(curve)}];
      parameters = nullptr;
      for (auto& [first, shared] : same_hash) {
        if (SameCurveTimes(set.curves[first], curve)) {
          parameters = &shared;
          break;
        }
      }
      if (parameters == nullptr) {
        same_hash.emplace_back(c, SharedParameters());
        parameters = &same_hash.back().second;
      }
    }
    result.curves[c] = RetimeOne(curve, set.beziers_restricted, result.timings[t], taus[t], grid, t,
                                 histograms[t], *parameters, is_given && given->second.exact_taus);
  }
  return group;
}

}  // namespace

KomaUchiResult RetimeCurves(const CurveSet& set, const KomaUchiOptions& options) {
  KomaUchiResult result;
  const std::optional<FilmGrid> grid = FilmGrid::Make(set.fps, options.timing_fps);
  if (grid) result.timing_fps = grid->timing_fps();
  const std::vector<std::vector<int>> members = GroupMembers(options, set);
  result.curves.resize(set.curves.size());
  // The default group first: its key poses are the answer's, its first timing is timings[0].
  TimingGroupResult body = RetimeGroup(set, members.back(), options, /*keep=*/false,
                                       std::string(kDefaultTimingGroupName), result);
  body.name = std::string(kDefaultTimingGroupName);
  result.key_frames = body.key_frames;
  result.key_grid_frames = body.key_grid_frames;
  result.key_merged = body.key_merged;
  std::vector<TimingGroupResult> named;
  for (size_t g = 0; g < options.groups.size(); ++g) {
    named.push_back(RetimeGroup(set, members[g], GroupOptions(options, options.groups[g]),
                                options.groups[g].mode == TimingGroupMode::kKeep,
                                options.groups[g].name, result));
    named.back().name = options.groups[g].name;
  }
  // Listed only when some curve is in a named group: a request whose curves are all in the
  // default group answers as one without groups.
  if (members.back().size() < set.curves.size()) {
    result.groups.push_back(std::move(body));
    for (TimingGroupResult& g : named) result.groups.push_back(std::move(g));
  }
  return result;
}

}  // namespace koma
