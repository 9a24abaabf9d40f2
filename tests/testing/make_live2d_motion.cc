// Writes a generated Live2D-like motion (tests/testing/live2d_motion.h) as a motion3.json on
// standard output, for the end-to-end tests: make_live2d_motion FPS CURVES SECONDS SEED.
#include <cstdlib>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/testing/live2d_motion.h"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: make_live2d_motion FPS CURVES SECONDS SEED\n";
    return 2;
  }
  koma::testing::Live2dMotionSpec spec;
  spec.fps = std::atof(argv[1]);
  spec.curve_count = std::atoi(argv[2]);
  spec.seconds = std::atof(argv[3]);
  spec.seed = std::strtoull(argv[4], nullptr, 10);
  const koma::CurveSet set = koma::testing::Live2dMotion(spec);
  nlohmann::ordered_json curves = nlohmann::ordered_json::array();
  int segments = 0, points = 0;
  const auto seconds = [&set](double frame) { return frame / set.fps; };
  for (const koma::Curve& curve : set.curves) {
    nlohmann::ordered_json s = nlohmann::ordered_json::array();
    s.push_back(seconds(curve.start.frame));
    s.push_back(curve.start.value);
    ++points;
    for (const koma::CurveSegment& segment : curve.segments) {
      s.push_back(static_cast<int>(segment.type));
      if (segment.type == koma::SegmentType::kBezier) {
        for (const koma::CurvePoint& h : segment.handles) {
          s.push_back(seconds(h.frame));
          s.push_back(h.value);
        }
        points += 2;
      }
      s.push_back(seconds(segment.end.frame));
      s.push_back(segment.end.value);
      ++points;
      ++segments;
    }
    curves.push_back({{"Target", "Parameter"}, {"Id", curve.id}, {"Segments", s}});
  }
  nlohmann::ordered_json motion = {
      {"Version", 3},
      {"Meta",
       {{"Duration", seconds(set.frame_count - 1)},
        {"Fps", set.fps},
        {"Loop", false},
        {"AreBeziersRestricted", set.beziers_restricted},
        {"CurveCount", set.curves.size()},
        {"TotalSegmentCount", segments},
        {"TotalPointCount", points},
        {"UserDataCount", 0},
        {"TotalUserDataSize", 0}}},
      {"Curves", curves}};
  std::cout << motion.dump(1, '\t') << "\n";
  return 0;
}
