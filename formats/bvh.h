// BVH (Biovision Hierarchy) motion capture files <-> SkeletalClip.
//
// A BVH file is a HIERARCHY section (ROOT/JOINT blocks with OFFSET, CHANNELS and End Site
// blocks) followed by a MOTION section ("Frames: N", "Frame Time: seconds", then N frames of
// channel values in joint declaration order).
#ifndef KOMA_FORMATS_BVH_H_
#define KOMA_FORMATS_BVH_H_

#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "core/skeleton.h"

namespace koma::formats {

// Reads a whole BVH file.
//
// Accepted: any mix of spaces, tabs, blank lines and LF/CRLF/CR line endings; one or more
// ROOT blocks; 0-6 CHANNELS per joint in any order (a joint without a CHANNELS line has
// none); any number of End Sites per joint, kept in Joint::end_sites; joint names are single
// tokens; "Frames: 0". The motion values are read as one stream of exactly
// Frames x ChannelCount numbers, so a frame may be wrapped over several lines. The frame time
// is kept exactly as the double nearest to its text.
//
// Errors are INVALID_ARGUMENT with "line L: " and the offending token (quoted, at most 40
// bytes), for example
//   line 12: unknown channel name "Xrot" (expected Xposition, ...)
//   line 140: expected 96 values per frame (frame 3 of 0..129), got 40 before the end of ...
// for: a missing or misplaced keyword, unbalanced braces, a malformed or non-finite number,
// a CHANNELS count outside 0..6, a repeated channel, OFFSET or CHANNELS line, a duplicate
// joint name, a joint or End Site without OFFSET, an End Site with channels or children, a
// negative or malformed frame count, a frame time that is not > 0, too few motion values,
// and values after the last frame that are not whole frames. Frames in messages count from
// 0. The result passes ValidateSkeleton.
//
// Read with a warning (appended to `warnings` when given, "line L: ..."): more whole frames
// after the "Frames:" count than it says, as some exporters write (assimp's Boxing_Toes test
// file: "Frames: 3069" and 3,070 rows). Blender's importer reads them all, so koma does; the
// clip's frame_count is the frames read. A partial frame after them is still an error.
absl::StatusOr<SkeletalClip> ParseBvh(std::string_view text,
                                      std::vector<std::string>* warnings = nullptr);

// Writes `clip` in the common layout: tab indentation, "ROOT"/"JOINT"/"End Site" blocks with
// braces on their own lines, "OFFSET x y z", "CHANNELS n ..." (also for n = 0), "MOTION",
// "Frames: N", "Frame Time: t", one line per frame with values separated by single spaces,
// LF line endings, every number written by FormatDouble.
//
// Joints are written depth-first: the children of a joint are the later joints whose parent
// it is, in index order, and its End Sites follow its child joints. Frame values are written
// in that order too, so a clip whose joints are not depth-first reads back with its joints
// (and their values) reordered. ParseBvh(WriteBvh(clip)) gives the same numbers (-0 reads
// back as +0), and WriteBvh(ParseBvh(WriteBvh(c))) == WriteBvh(c) byte for byte.
//
// Requires ValidateSkeleton(clip.skeleton) OK, frame_count >= 0,
// values.size() == frame_count x ChannelCount(skeleton), finite numbers, and joint names
// that are single non-empty tokens without whitespace (as ParseBvh produces); checked with
// assert only.
std::string WriteBvh(const SkeletalClip& clip);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_BVH_H_
