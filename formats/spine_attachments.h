// Spine slot attachment timelines (the drawing a slot shows over time): the names a slot can
// show, its keys in an animation, and WriteSpineAttachments, which replaces slots' attachment
// timelines in one animation (`koma lipblink` on a Spine skeleton: the mouth and eye slots).
//
// Written from the published JSON format (esotericsoftware.com/spine-json-format, 3.7, 3.8 and
// 4.x): animations.<animation>.slots.<slot>.attachment is a list of keys
// {"time": seconds, "name": attachment or null}, the same in every version (4.x may omit a
// time of 0); the slot shows its setup attachment (slots[].attachment) before the first key.
// Skins: 3.x before 3.8 is an object {skin: {slot: {attachment: {...}}}}, 3.8 and 4.x a list
// [{"name": skin, "attachments": {slot: {attachment: {...}}}}].
#ifndef KOMA_FORMATS_SPINE_ATTACHMENTS_H_
#define KOMA_FORMATS_SPINE_ATTACHMENTS_H_

#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "formats/spine.h"

namespace koma::formats {

struct SpineAttachmentKey {
  double time = 0.0;  // seconds
  std::string name;   // the attachment shown from `time` on
  friend bool operator==(const SpineAttachmentKey& a, const SpineAttachmentKey& b) {
    return a.time == b.time && a.name == b.name;
  }
};

struct SpineAttachmentTimeline {
  std::string slot;
  std::vector<SpineAttachmentKey> keys;  // times strictly increasing
};

// The attachment names `slot` has in any skin, in file order (skins in order, duplicates
// once). NOT_FOUND when the skeleton has no slot named `slot` (listing the slots).
absl::StatusOr<std::vector<std::string>> SpineSlotAttachments(const SpineFile& file,
                                                              std::string_view slot);

// The slot's setup attachment (slots[].attachment), empty when none.
std::string SpineSetupAttachment(const SpineFile& file, std::string_view slot);

// The keys of `slot`'s attachment timeline in `animation` (empty when the animation or the
// timeline does not exist). A null name is read as "". INVALID_ARGUMENT naming the JSON path
// for keys that are not objects, non-numeric times, or names that are neither strings nor null.
absl::StatusOr<std::vector<SpineAttachmentKey>> SpineAttachmentKeys(const SpineFile& file,
                                                                    std::string_view animation,
                                                                    std::string_view slot);

// file.document with each timeline's slot attachment timeline in `animation` replaced by its
// keys ({"time", "name"}, a time of 0 omitted in 4.x as the editor exports it), the slot's
// other timelines (color, ...) and everything else kept in place. A missing animation, or a
// missing "slots" object in it, is added at the end. Output as WriteSpine's: tab-indented, LF,
// a final newline, whole numbers as integers. INVALID_ARGUMENT for an empty animation name, a
// slot the skeleton lacks, no keys, times that are not finite, negative or not increasing.
absl::StatusOr<std::string> WriteSpineAttachments(
    const SpineFile& file, std::string_view animation,
    const std::vector<SpineAttachmentTimeline>& timelines);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_SPINE_ATTACHMENTS_H_
