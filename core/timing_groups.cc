#include "core/timing_groups.h"

namespace koma {

bool IdMatches(absl::string_view pattern, absl::string_view id) {
  size_t p = 0, i = 0;
  size_t star = absl::string_view::npos;  // the last '*' seen, and where its run ended
  size_t resume = 0;
  while (i < id.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == id[i])) {
      ++p;
      ++i;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      resume = i;
    } else if (star != absl::string_view::npos) {
      p = star + 1;  // let the last '*' take one character more
      i = ++resume;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

int GroupOf(const std::vector<CurveTimingGroup>& groups, absl::string_view id) {
  for (size_t g = 0; g < groups.size(); ++g) {
    for (const std::string& pattern : groups[g].ids) {
      if (IdMatches(pattern, id)) return static_cast<int>(g);
    }
  }
  return static_cast<int>(groups.size());
}

std::vector<CurveTimingGroup> DefaultLive2dTimingGroups() {
  CurveTimingGroup face;
  face.name = "face";
  face.ids = {"ParamEye*", "ParamBrow*", "ParamMouth*", "ParamCheek"};
  face.mode = TimingGroupMode::kLipBlink;
  CurveTimingGroup hair;
  hair.name = "hair";
  hair.ids = {"ParamHair*", "ParamBust*", "ParamSkirt*", "ParamRibbon*"};
  return {face, hair};
}

}  // namespace koma
