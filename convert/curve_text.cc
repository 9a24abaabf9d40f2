#include "convert/curve_text.h"

#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "formats/curve_csv.h"
#include "formats/error_text.h"

namespace koma::convert {

absl::StatusOr<CurveInput> ParseCurveText(std::string_view text, bool csv, double csv_fps) {
  CurveInput input;
  if (csv) {
    absl::StatusOr<CurveSet> set = formats::ParseCurveCsv(text, csv_fps);
    if (!set.ok()) return set.status();
    input.curves = *std::move(set);
    return input;
  }
  absl::StatusOr<formats::Motion3File> file = formats::ParseMotion3(text);
  if (!file.ok()) return file.status();
  input.curves = file->curves;
  input.motion3 = *std::move(file);
  return input;
}

absl::Status SelectSpineAnimation(CurveInput& input, int index) {
  const formats::SpineAnimation& animation = input.spine->animations[index];
  if (!animation.retimable()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "animation ", formats::QuoteForError(animation.name),
        " has no bone rotate, translate, scale or shear keys to retime over two frames or more"));
  }
  input.spine_animation = index;
  input.curves = animation.curves;
  return absl::OkStatus();
}

absl::StatusOr<CurveInput> ParseSpineText(std::string_view text, std::string_view animation) {
  absl::StatusOr<formats::SpineFile> file = formats::ParseSpine(text);
  if (!file.ok()) return file.status();
  return SpineCurveInput(*std::move(file), animation);
}

absl::StatusOr<CurveInput> SpineCurveInput(formats::SpineFile file, std::string_view animation) {
  CurveInput input;
  input.spine = std::move(file);
  int index = -1;
  if (!animation.empty()) {
    absl::StatusOr<int> found = formats::FindSpineAnimation(*input.spine, animation);
    if (!found.ok()) return found.status();
    index = *found;
  } else {
    std::vector<std::string> retimable;
    for (size_t i = 0; i < input.spine->animations.size(); ++i) {
      if (!input.spine->animations[i].retimable()) continue;
      retimable.push_back(formats::QuoteForError(input.spine->animations[i].name));
      index = static_cast<int>(i);
    }
    if (retimable.size() != 1) {
      return absl::InvalidArgumentError(
          retimable.empty()
              ? std::string("the skeleton has no animation with bone keys to retime")
              : absl::StrCat("name the animation to retime: the skeleton has ", retimable.size(),
                             " (", absl::StrJoin(retimable, ", "), ")"));
    }
  }
  if (absl::Status s = SelectSpineAnimation(input, index); !s.ok()) return s;
  return input;
}

absl::StatusOr<std::string> CurveOutputText(
    const CurveInput& input, const std::vector<std::optional<CurveReplacement>>& replacements,
    bool csv) {
  const CurveSet& set = input.curves;
  if (csv) {
    std::vector<std::string> ids;
    std::vector<std::vector<double>> values;
    for (size_t i = 0; i < set.curves.size(); ++i) {
      ids.push_back(set.curves[i].id);
      values.push_back(replacements[i] ? replacements[i]->values
                                       : SampleEveryFrame(set.curves[i], set.frame_count,
                                                          set.beziers_restricted));
    }
    return formats::WriteCurveCsv(ids, values);
  }
  if (!input.motion3 && !input.spine) {
    return absl::InvalidArgumentError("a CSV input can only be written as CSV");
  }
  std::vector<std::optional<std::vector<CurvePoint>>> stepped;
  for (const std::optional<CurveReplacement>& r : replacements) {
    stepped.push_back(r ? std::optional<std::vector<CurvePoint>>(r->steps) : std::nullopt);
  }
  if (input.spine) {
    return formats::WriteSpine(*input.spine,
                               {formats::SpineRetimed{input.spine_animation, std::move(stepped)}});
  }
  return formats::WriteMotion3(*input.motion3, stepped);
}

}  // namespace koma::convert
