// ParseBvh: a single pass over whitespace-separated tokens. The hierarchy is read with an explicit
// stack of open blocks (no recursion, so deep nesting cannot overflow the call stack); the motion
// section is one stream of Frames x channels numbers.
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "formats/bvh.h"
#include "formats/bvh_lexer.h"
#include "formats/error_text.h"
#include "formats/number_format.h"
#include "formats/text_encoding.h"

namespace koma::formats {
namespace {

constexpr int kMaxChannelsPerJoint = 6;

// A ROOT/JOINT or End Site block whose "}" has not been read yet.
struct OpenBlock {
  int joint = 0;          // index into Skeleton::joints
  bool end_site = false;  // an End Site of `joint` (its last end_sites entry)
  int line = 0;           // line of the keyword that opened it
  bool has_offset = false;
  bool has_channels = false;
};

class BvhParser {
 public:
  BvhParser(std::string_view text, std::vector<std::string>* warnings)
      : lexer_(text), text_(text), warnings_(warnings) {}

  absl::StatusOr<SkeletalClip> Parse() {
    KOMA_RETURN_IF_ERROR(ParseHierarchy());
    KOMA_RETURN_IF_ERROR(ParseMotionHeader());
    KOMA_RETURN_IF_ERROR(ParseMotionValues());
    KOMA_RETURN_IF_ERROR(ValidateSkeleton(clip_.skeleton));
    return std::move(clip_);
  }

 private:
  // "line N: message". A word that runs into the very end of the file (no line end after it)
  // is where a cut-off copy or download stops: "Xrotati" there is a truncated file far more
  // often than a typo, so the message says so.
  absl::Status Error(const BvhToken& token, const std::string& message) const {
    const bool cut_off =
        !token.text.empty() && token.text.data() + token.text.size() == text_.data() + text_.size();
    return absl::InvalidArgumentError(absl::StrCat(
        "line ", token.line, ": ", message,
        cut_off ? " (the file ends in the middle of this word: is it cut short?)" : ""));
  }

  std::string BlockName(const OpenBlock& block) const {
    const std::string& name = clip_.skeleton.joints[block.joint].name;
    return absl::StrCat(block.end_site ? "End Site of joint " : "joint ", QuoteForError(name),
                        " (line ", block.line, ")");
  }

  absl::Status Expect(std::string_view keyword, std::string_view after) {
    const BvhToken token = lexer_.Next();
    if (token.text == keyword) return absl::OkStatus();
    return Error(token, absl::StrCat("expected \"", std::string(keyword), "\"", std::string(after),
                                     ", got ", DescribeToken(token)));
  }

  // `token` as a finite double; `what` names the field in the error.
  absl::StatusOr<double> NumberAt(const BvhToken& token, std::string_view what) const {
    absl::StatusOr<double> value = ParseDouble(token.text);
    if (!value.ok()) {
      return Error(token, absl::StrCat(std::string(what), ": ", value.status().message()));
    }
    return *value;
  }
  absl::StatusOr<double> ReadNumber(std::string_view what) { return NumberAt(lexer_.Next(), what); }

  // The next token as a non-negative decimal integer that fits an int.
  absl::StatusOr<int> ReadCount(std::string_view what) {
    const BvhToken token = lexer_.Next();
    count_line_ = token.line;
    int value = 0;
    const char* end = token.text.data() + token.text.size();
    const auto [ptr, ec] = std::from_chars(token.text.data(), end, value);
    if (ec != std::errc() || ptr != end || token.text.empty() || value < 0) {
      return Error(token, absl::StrCat(std::string(what), ": expected a non-negative integer, got ",
                                       DescribeToken(token)));
    }
    return value;
  }

  absl::Status ParseHierarchy() {
    KOMA_RETURN_IF_ERROR(Expect("HIERARCHY", " at the start of the file"));
    while (true) {
      const BvhToken token = lexer_.Next();
      if (!open_.empty()) {
        KOMA_RETURN_IF_ERROR(ParseBlockItem(token));
      } else if (token.text == "ROOT") {
        KOMA_RETURN_IF_ERROR(OpenJoint(token, -1));
      } else if (token.text == "MOTION" && !clip_.skeleton.joints.empty()) {
        return absl::OkStatus();
      } else {
        return Error(token, absl::StrCat(clip_.skeleton.joints.empty()
                                             ? "expected \"ROOT\", got "
                                             : "expected \"ROOT\" or \"MOTION\", got ",
                                         DescribeToken(token)));
      }
    }
  }

  absl::Status ParseBlockItem(const BvhToken& token) {
    const OpenBlock& block = open_.back();
    if (token.text == "OFFSET") return ParseOffset(token);
    if (token.text == "}") return CloseBlock(token);
    if (token.text.empty() || token.text == "ROOT" || token.text == "MOTION") {
      return Error(token, absl::StrCat(DescribeToken(token), " inside ", BlockName(block),
                                       ": missing \"}\""));
    }
    const bool joint_item =
        token.text == "CHANNELS" || token.text == "JOINT" || token.text == "End";
    if (block.end_site && joint_item) {
      return Error(token, absl::StrCat("unexpected ", DescribeToken(token), " in ",
                                       BlockName(block), ": an End Site holds only OFFSET"));
    }
    if (token.text == "CHANNELS") return ParseChannels(token);
    if (token.text == "JOINT") return OpenJoint(token, block.joint);
    if (token.text == "End") return OpenEndSite(token);
    return Error(token, absl::StrCat("unexpected ", DescribeToken(token), " in ", BlockName(block),
                                     " (expected OFFSET, CHANNELS, JOINT, End Site or \"}\")"));
  }

  absl::Status OpenJoint(const BvhToken& keyword, int parent) {
    const BvhToken name = lexer_.Next();
    if (name.text.empty() || name.text == "{" || name.text == "}") {
      return Error(name, absl::StrCat("expected a joint name after \"", std::string(keyword.text),
                                      "\", got ", DescribeToken(name)));
    }
    const auto [it, inserted] = name_lines_.emplace(name.text, name.line);
    if (!inserted) {
      return Error(name, absl::StrCat("duplicate joint name ", QuoteForError(name.text),
                                      " (first declared on line ", it->second, ")"));
    }
    KOMA_RETURN_IF_ERROR(Expect(
        "{", absl::StrCat(" after ", std::string(keyword.text), " ", QuoteForError(name.text))));
    Joint joint;
    joint.name = std::string(name.text);
    joint.parent = parent;
    clip_.skeleton.joints.push_back(std::move(joint));
    open_.push_back(
        OpenBlock{static_cast<int>(clip_.skeleton.joints.size()) - 1, false, keyword.line});
    return absl::OkStatus();
  }

  absl::Status OpenEndSite(const BvhToken& keyword) {
    KOMA_RETURN_IF_ERROR(Expect("Site", " after \"End\""));
    KOMA_RETURN_IF_ERROR(Expect("{", " after \"End Site\""));
    const int joint = open_.back().joint;
    clip_.skeleton.joints[joint].end_sites.emplace_back();
    open_.push_back(OpenBlock{joint, true, keyword.line});
    return absl::OkStatus();
  }

  absl::Status CloseBlock(const BvhToken& token) {
    if (!open_.back().has_offset) {
      return Error(token, absl::StrCat(BlockName(open_.back()), " has no OFFSET"));
    }
    open_.pop_back();
    return absl::OkStatus();
  }

  absl::Status ParseOffset(const BvhToken& keyword) {
    OpenBlock& block = open_.back();
    if (block.has_offset) {
      return Error(keyword, absl::StrCat("second OFFSET in ", BlockName(block)));
    }
    block.has_offset = true;
    Vec3 offset;
    KOMA_ASSIGN_OR_RETURN(offset.x, ReadNumber("OFFSET x"));
    KOMA_ASSIGN_OR_RETURN(offset.y, ReadNumber("OFFSET y"));
    KOMA_ASSIGN_OR_RETURN(offset.z, ReadNumber("OFFSET z"));
    Joint& joint = clip_.skeleton.joints[block.joint];
    (block.end_site ? joint.end_sites.back() : joint.offset) = offset;
    return absl::OkStatus();
  }

  absl::Status ParseChannels(const BvhToken& keyword) {
    OpenBlock& block = open_.back();
    if (block.has_channels) {
      return Error(keyword, absl::StrCat("second CHANNELS in ", BlockName(block)));
    }
    block.has_channels = true;
    KOMA_ASSIGN_OR_RETURN(const int count, ReadCount("CHANNELS count"));
    if (count > kMaxChannelsPerJoint) {
      return Error(keyword, absl::StrCat("CHANNELS count ", count, " in ", BlockName(block),
                                         " is more than ", kMaxChannelsPerJoint));
    }
    ChannelList& channels = clip_.skeleton.joints[block.joint].channels;
    for (int i = 0; i < count; ++i) {
      const BvhToken token = lexer_.Next();
      absl::StatusOr<ChannelKind> kind = ParseChannelName(token.text);
      if (!kind.ok()) {  // not kind.status(): it would quote all of a long token
        return Error(token, absl::StrCat("unknown channel name ", DescribeToken(token),
                                         " (expected Xposition, Yposition, Zposition, "
                                         "Xrotation, Yrotation or Zrotation)"));
      }
      for (ChannelKind seen : channels) {
        if (seen == *kind) {
          return Error(token, absl::StrCat("channel ", QuoteForError(token.text),
                                           " listed twice in ", BlockName(block)));
        }
      }
      channels.push_back(*kind);
    }
    return absl::OkStatus();
  }

  absl::Status ParseMotionHeader() {
    KOMA_RETURN_IF_ERROR(Expect("Frames:", " after \"MOTION\""));
    KOMA_ASSIGN_OR_RETURN(clip_.frame_count, ReadCount("Frames"));
    frames_line_ = count_line_;
    KOMA_RETURN_IF_ERROR(Expect("Frame", " after the frame count"));
    KOMA_RETURN_IF_ERROR(Expect("Time:", " after \"Frame\""));
    const BvhToken token = lexer_.Next();
    frame_time_line_ = token.line;
    KOMA_ASSIGN_OR_RETURN(clip_.frame_time, NumberAt(token, "Frame Time"));
    if (clip_.frame_time <= 0.0) {  // NumberAt already rejects NaN and infinities
      return Error(token,
                   absl::StrCat("Frame Time ", DescribeToken(token), " must be > 0 seconds"));
    }
    return absl::OkStatus();
  }

  absl::Status ParseMotionValues() {
    const int64_t channels = ChannelCount(clip_.skeleton);
    const int64_t total = channels * clip_.frame_count;
    // A value takes at least 2 bytes (a digit and a separator): never reserve more than the text
    // could hold, whatever "Frames:" claims.
    clip_.values.reserve(static_cast<size_t>(std::min<int64_t>(total, text_.size() / 2 + 1)));
    int last_line = frame_time_line_;  // where the last value (or the header) was read
    for (int64_t i = 0; i < total; ++i) {
      const BvhToken token = lexer_.Next();
      if (token.text.empty()) return MissingValues(last_line, i, channels);
      const absl::StatusOr<double> value = ParseDouble(token.text);
      if (!value.ok()) {  // ValueName walks the joints: only on failure
        return Error(token, absl::StrCat(ValueName(i, channels), ": ", value.status().message()));
      }
      clip_.values.push_back(*value);
      last_line = token.line;
    }
    return ParseExtraFrames(channels, total);
  }

  // Whole frames after the `Frames:` count (some exporters count one frame less than they
  // write; Blender's importer reads them all): read too, with a warning naming both counts.
  // Anything else after the last frame is the error it always was, at the word that is not a
  // number or at the start of the frame left incomplete.
  absl::Status ParseExtraFrames(int64_t channels, int64_t total) {
    BvhToken token = lexer_.Next();
    if (token.text.empty()) return absl::OkStatus();
    if (channels == 0) return UnexpectedAfterFrames(token, channels, total);
    const int first_line = token.line;
    BvhToken frame_start = token;  // first value of the frame being read
    int64_t extra = 0;             // values read after the counted frames
    for (; !token.text.empty(); token = lexer_.Next(), ++extra) {
      if (extra % channels == 0) frame_start = token;
      const absl::StatusOr<double> value = ParseDouble(token.text);
      if (!value.ok()) return UnexpectedAfterFrames(token, channels, total);
      clip_.values.push_back(*value);
    }
    const int64_t frames = clip_.frame_count + extra / channels;
    if (extra % channels != 0 || frames > INT32_MAX) {
      return UnexpectedAfterFrames(frame_start, channels, total);
    }
    if (warnings_ != nullptr) {
      warnings_->push_back(absl::StrCat("line ", first_line, ": \"Frames: ", clip_.frame_count,
                                        "\" (line ", frames_line_, ") but ", frames,
                                        " frames follow; read all ", frames, ", as Blender does"));
    }
    clip_.frame_count = static_cast<int>(frames);
    return absl::OkStatus();
  }

  absl::Status UnexpectedAfterFrames(const BvhToken& token, int64_t channels, int64_t total) const {
    return Error(token, absl::StrCat("unexpected ", DescribeToken(token),
                                     " after the last frame (expected ", clip_.frame_count,
                                     " frames x ", channels, " values = ", total, ")"));
  }

  // The file ended after `read` of the frame_count x `channels` values; `line` is where the last
  // value (or, before any, the frame time) was read.
  absl::Status MissingValues(int line, int64_t read, int64_t channels) const {
    const BvhToken at{"", line};
    const int64_t frame = read / channels;
    if (read % channels == 0) {
      return Error(at, absl::StrCat("expected ", clip_.frame_count, " frames of ", channels,
                                    " values, got ", frame, " before the end of the file"));
    }
    return Error(at, absl::StrCat("expected ", channels, " values per frame (frame ", frame,
                                  " of 0..", clip_.frame_count - 1, "), got ", read % channels,
                                  " before the end of the file"));
  }

  // "frame 3, channel 5 (\"Hips\" Xrotation)" for the value at `index` of the motion stream.
  std::string ValueName(int64_t index, int64_t channels) const {
    const int64_t frame = index / channels;
    int64_t channel = index % channels;
    for (const Joint& joint : clip_.skeleton.joints) {
      const int64_t count = static_cast<int64_t>(joint.channels.size());
      if (channel < count) {
        return absl::StrCat("frame ", frame, ", channel ", index % channels, " (",
                            QuoteForError(joint.name), " ",
                            std::string(ChannelName(joint.channels[channel])), ")");
      }
      channel -= count;
    }
    return absl::StrCat("frame ", frame);  // not reached: index < frames x channels
  }

  BvhLexer lexer_;
  std::string_view text_;    // all of the input (the lexer's tokens point into it)
  std::vector<std::string>* warnings_;  // where a rule was bent; nullptr: not wanted
  int count_line_ = 0;       // line of the count ReadCount read last
  int frames_line_ = 0;      // line of the "Frames:" count
  int frame_time_line_ = 0;  // line of the "Frame Time:" value
  SkeletalClip clip_;
  std::vector<OpenBlock> open_;
  std::unordered_map<std::string_view, int> name_lines_;  // joint name -> line declared
};

}  // namespace

absl::StatusOr<SkeletalClip> ParseBvh(std::string_view text, std::vector<std::string>* warnings) {
  // A UTF-8 byte order mark is skipped (line numbers are unchanged); UTF-16 is refused.
  KOMA_ASSIGN_OR_RETURN(text, SkipUtf8Bom(text));
  return BvhParser(text, warnings).Parse();
}

}  // namespace koma::formats
