// Writes the RetimeSkeletal report of a small hand-made call with a camera, for report_test.sh
// camera (the koma CLI has no camera option):
//   write_camera_report OUT.html
// The clip: 48 frames at 24 fps, positions form, a root at (0.5 f, 0, 0) and a hand at
// (0.5 f + sin f, 10, cos f) in frame f. The camera (column-major) scales x by 0.1 and y by
// 0.2 and divides by w = 1 + 0.01 z. The response shows frame f's source frame f - f % 2 (on
// twos). report_checks.py camera recomputes the projection on its own.
#include <cmath>
#include <cstdio>

#include "client/report/skeletal_report.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_camera_report OUT.html\n");
    return 2;
  }
  constexpr int kFrames = 48;
  koma::v1::RetimeSkeletalRequest request;
  koma::v1::SkeletalMotion* motion = request.mutable_motion();
  koma::v1::Joint* root = motion->mutable_skeleton()->add_joints();
  root->set_name("Hips");
  root->set_parent(-1);
  koma::v1::Joint* hand = motion->mutable_skeleton()->add_joints();
  hand->set_name("Hand");
  hand->set_parent(0);
  motion->set_frame_time(1.0 / 24);
  motion->set_frame_count(kFrames);
  for (int f = 0; f < kFrames; ++f) {
    for (double v : {0.5 * f, 0.0, 0.0, 0.5 * f + std::sin(f), 10.0, std::cos(f)}) {
      motion->mutable_positions()->add_values(v);
    }
  }
  for (double v :
       {0.1, 0.0, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 0.0, 1.0, 0.01, 0.0, 0.0, 0.0, 1.0}) {
    request.add_camera(v);
  }
  koma::v1::RetimeSkeletalResponse response;
  for (int f = 0; f < kFrames; ++f) {
    response.add_source_frames(f - f % 2);
    response.add_kinds(f % 2 ? koma::v1::HELD : koma::v1::ORIGINAL);
    response.add_input_ssd(f == 0 ? 0.0 : 1.0);
  }
  const absl::Status status =
      koma::client::report::WriteSkeletalReport(argv[1], request, response, "camera clip");
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", std::string(status.message()).c_str());
    return 1;
  }
  return 0;
}
