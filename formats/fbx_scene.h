// The animation of a binary FBX file (formats/fbx.h): its models (the nodes: LimbNode bones,
// Nulls, meshes), their transforms, and one take's curves, as core/fbx_rig.h evaluates them.
//
// What is read: GlobalSettings' TimeMode and CustomFrameRate (the take's frame rate); the
// Model objects' Properties70 over the Definitions' FbxNode template (Lcl Translation,
// Rotation, Scaling, Pre/PostRotation, RotationOrder, RotationActive, the offsets and pivots);
// the AnimationStacks (takes) with their LocalStart/LocalStop, their AnimationLayers,
// AnimationCurveNodes (T, R, S) and AnimationCurves (KeyTime, KeyValueFloat, and
// KeyAttrFlags/KeyAttrDataFloat/KeyAttrRefCount: each key's interpolation, slopes and
// weights); and the Connections that tie them together.
#ifndef KOMA_FORMATS_FBX_SCENE_H_
#define KOMA_FORMATS_FBX_SCENE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "core/fbx_rig.h"
#include "formats/fbx.h"

namespace koma::formats {

struct FbxTakeInfo {
  std::string name;
  int64_t start = 0, stop = 0;  // ticks (LocalStart, LocalStop)
  int layers = 0;
};

struct FbxTakeRig {
  double fps = 0;  // the file's frame rate (GlobalSettings' TimeMode / CustomFrameRate)
  FbxTakeInfo take;
  std::vector<FbxTakeInfo> takes;  // every AnimationStack, in file order
  // The models that move or are bones (LimbNode, Root, Null), and their ancestors; parents
  // before children. rig.nodes[i] is model names[i].
  FbxRig rig;
  std::vector<std::string> names;
  std::vector<std::string> types;  // "LimbNode", "Null", "Mesh", ...
  std::vector<int64_t> ids;        // the Model objects' ids
  // Each rig curve's AnimationCurve object id (where a writer puts new keys).
  std::vector<int64_t> curve_ids;
};

// The take named `take` ("": the file's current take, Takes/Current, else the first stack).
// INVALID_ARGUMENT naming the object and field for what does not read (a curve whose value
// count differs from its key count, a connection to nothing, a take that does not exist:
// "take \"Run\": not in the file (it has \"Take 001\", \"Walk\")").
absl::StatusOr<FbxTakeRig> ReadFbxTakeRig(const FbxDocument& document, const std::string& take);

// The file with the take's curves replaced by a key on every output frame (ticks from the
// take's start at `output_fps`), each holding the value the curve has at `sample_ticks[k]`
// (the source time of the drawing frame k shows), with the constant flag: every reader (the
// FBX SDK's, and Blender's, assimp's and three.js's, which interpolate linearly whatever the
// flags) shows the holds. The take's LocalStop/ReferenceStop and Takes' times follow the new
// length; a new rate sets GlobalSettings' TimeMode (and CustomFrameRate when it has no mode).
// Every other node is written as it was.
absl::StatusOr<std::string> WriteFbxRetimed(FbxDocument document, const FbxTakeRig& rig,
                                            const std::vector<int64_t>& sample_ticks,
                                            double output_fps);

// FBX's TimeMode numbers as frames per second (14, custom: `custom_rate`); 0 when unknown.
double FbxTimeModeFps(int64_t time_mode, double custom_rate);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_FBX_SCENE_H_
