// Prints an FBX file's take as koma reads it, for tests that compare it with other readers:
// JSON {"fps", "start_s", "frames", "names": [...], "types": [...], "positions": [[x, y, z]
// per node, per frame]}, the take's frames from its start (formats/fbx_scene.h).
//   fbx_positions FILE.fbx FRAMES [TAKE]
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "core/fbx_rig.h"
#include "formats/fbx.h"
#include "formats/fbx_scene.h"
#include "nlohmann/json.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: fbx_positions FILE.fbx FRAMES [TAKE]\n";
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  absl::StatusOr<koma::formats::FbxDocument> document = koma::formats::ReadFbx(bytes.str());
  if (!document.ok()) {
    std::cerr << argv[1] << ": " << document.status().message() << "\n";
    return 1;
  }
  absl::StatusOr<koma::formats::FbxTakeRig> rig =
      koma::formats::ReadFbxTakeRig(*document, argc > 3 ? argv[3] : "");
  if (!rig.ok()) {
    std::cerr << argv[1] << ": " << rig.status().message() << "\n";
    return 1;
  }
  const int64_t frames = std::stoll(argv[2]);
  const std::vector<double> positions =
      koma::FbxNodePositions(rig->rig, rig->take.start, rig->fps, frames);
  nlohmann::json out;
  out["fps"] = rig->fps;
  out["start_s"] = static_cast<double>(rig->take.start) / koma::kFbxTicksPerSecond;
  out["frames"] = frames;
  out["names"] = rig->names;
  out["types"] = rig->types;
  nlohmann::json all = nlohmann::json::array();
  const size_t n = rig->names.size();
  for (int64_t f = 0; f < frames; ++f) {
    nlohmann::json frame = nlohmann::json::array();
    for (size_t i = 0; i < n; ++i) {
      const double* p = positions.data() + (static_cast<size_t>(f) * n + i) * 3;
      frame.push_back({p[0], p[1], p[2]});
    }
    all.push_back(frame);
  }
  out["positions"] = all;
  std::cout << out.dump() << "\n";
  return 0;
}
