// Live2D Cubism motion3.json <-> CurveSet, keeping every field koma does not touch.
//
// A motion3.json file (spec: Live2D/CubismSpecs FileFormats/motion3.json.md) holds
//   Version, Meta {Duration (s), Fps, Loop, AreBeziersRestricted, FadeInTime (s),
//   FadeOutTime (s), CurveCount, TotalSegmentCount, TotalPointCount, UserDataCount,
//   TotalUserDataSize}, Curves [{Target, Id, FadeInTime?, FadeOutTime?, Segments}] and
//   UserData [{Time (s), Value}].
// Segments is one flat array of numbers: the first point (t in seconds, value), then per
// segment an identifier (0 linear, 1 bezier, 2 stepped, 3 inverse stepped) followed by its end
// point, or for a bezier by P1, P2 and P3.
#ifndef KOMA_FORMATS_MOTION3_H_
#define KOMA_FORMATS_MOTION3_H_

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "core/curves.h"

namespace koma::formats {

// Deepest JSON nesting ParseMotion3 accepts (a motion3.json file needs 3). Deeper input is
// refused before nlohmann parses it, so writing it back cannot exhaust the stack.
inline constexpr int kMaxMotion3Depth = 32;

// A time t x fps closer than this to an integer is that integer (frames).
inline constexpr double kFrameSnap = 1e-6;

struct Motion3File {
  // The whole file as parsed, object keys in file order: WriteMotion3 starts from it, so
  // fields koma does not know survive unchanged.
  nlohmann::ordered_json document;
  // Curves in file order, converted to frames: frame = t (s) x Meta.Fps, snapped to the
  // nearest integer when within kFrameSnap of it (so frame / fps read back is the frame).
  //   fps = Meta.Fps; frame_count = round(Meta.Duration x Meta.Fps) + 1;
  //   beziers_restricted = Meta.AreBeziersRestricted, false when absent: the Cubism SDK reads
  //   it with CubismJson's ToBoolean(), whose default is false (CubismMotionJson.cpp,
  //   GetEvaluationOptionFlag), and then solves Beziers on their handle times.
  // Curve ids are the Ids. Keyframe form only (no dense samples).
  CurveSet curves;
  // targets[i] = Curves[i].Target: "Model", "Parameter" or "PartOpacity".
  std::vector<std::string> targets;
};

// The Meta counts as the Cubism SDK counts them (Live2D/CubismNativeFramework
// src/Motion/CubismMotionJson.cpp HasConsistency() and CubismMotion.cpp Parse(), which sizes
// its point and segment buffers from TotalPointCount and TotalSegmentCount):
struct Motion3Counts {
  int curve_count = 0;          // entries of Curves
  int total_segment_count = 0;  // segments of all curves
  // Points of all curves: 1 per curve for its first point, +1 per linear, stepped or inverse
  // stepped segment, +3 per bezier segment (both handles count as points).
  int total_point_count = 0;
  int user_data_count = 0;  // entries of UserData (0 when absent)
  // Sum of the UTF-8 byte lengths of the UserData Values, without terminators: the spec's
  // example has "hoge" and "fuga" with 8, its schema says "total size of UserData in bytes";
  // the SDKs read the field (GetTotalEventValueSize, "total characters of the events") but do
  // not use it.
  int total_user_data_size = 0;
};
bool operator==(const Motion3Counts& a, const Motion3Counts& b);
bool operator!=(const Motion3Counts& a, const Motion3Counts& b);

// Parses a whole motion3.json file. INVALID_ARGUMENT, naming the JSON path and the value
// ("Curves[3].Segments[7]: expected a number, got \"x\""), for: malformed JSON (with
// nlohmann's byte offset), nesting deeper than kMaxMotion3Depth, a root that is not an object,
// missing or mistyped Meta, Meta.Fps (finite, > 0), Meta.Duration (finite, >= 0),
// Meta.AreBeziersRestricted (boolean), Curves, Target (one of the three), Id (string),
// curve FadeInTime/FadeOutTime (numbers), Segments (array of finite numbers: the first point
// and at least one segment), an unknown segment identifier, a segment cut short by the end of
// the array, and UserData entries (Time number, Value string). OUT_OF_RANGE when
// Duration x Fps does not fit an int frame count. The Meta counts are not checked (the SDK
// trusts them; WriteMotion3 rewrites them). Curve semantics (increasing times, handles inside
// their segment, unique ids) are ValidateCurveSet's job.
absl::StatusOr<Motion3File> ParseMotion3(std::string_view text);

// Counts `document`'s curves, segments, points and user data (see Motion3Counts), with the
// same structural checks and errors as ParseMotion3 for Curves, Segments and UserData.
absl::StatusOr<Motion3Counts> CountMotion3(const nlohmann::ordered_json& document);

// original.document with, for every i where stepped[i] has a value, Curves[i].Segments
// replaced by stepped keyframes: [t0, v0, 2, t1, v1, 2, t2, v2, ...] with t = frame / fps
// (fps = original.curves.fps) in seconds, then Meta's CurveCount, TotalSegmentCount,
// TotalPointCount, UserDataCount and TotalUserDataSize set to CountMotion3 of the result
// (added at the end of Meta when missing). Every other field keeps its value and position.
// Numbers that are integers are written as JSON integers ("1", not "1.0"); others with the
// shortest text that reads back to the same double (10 / 30 -> 0.3333333333333333).
//
// Output: one tab per indent level, ": " after keys, one value per line (the layout of Cubism
// Editor's exports), LF line endings, a final newline; invalid UTF-8 in strings is replaced
// by U+FFFD rather than failing.
//
// INVALID_ARGUMENT when stepped.size() != Curves.size(), fps is not finite and > 0, a
// replacement has fewer than 2 points, a non-finite number or frames that do not strictly
// increase ("stepped[2][4].frame: ..."), or the document fails CountMotion3 or has no Meta
// object.
absl::StatusOr<std::string> WriteMotion3(
    const Motion3File& original,
    const std::vector<std::optional<std::vector<CurvePoint>>>& stepped);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_MOTION3_H_
