// FBX's node transforms and animation curves, evaluated (plain types; formats/fbx_scene.h
// fills them from a file). Written from the FBX SDK's documented transform chain and curve
// definitions (FbxAnimCurveDef's flags), not from its code.
//
// A node's world transform:
//   World = ParentWorld * T * Roff * Rp * Rpre * R * Rpost^-1 * Rp^-1 * Soff * Sp * S * Sp^-1
// (for InheritType RSrs; FbxInheritType for the other two) with R the Euler rotation in the
// node's RotationOrder and Rpre, Rpost in XYZ order (both,
// and the order, only when RotationActive, as Blender's importer reads them). Angles in
// degrees; lengths in the file's unit.
#ifndef KOMA_CORE_FBX_RIG_H_
#define KOMA_CORE_FBX_RIG_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace koma {

// FBX time: 46,186,158,000 ticks a second.
inline constexpr int64_t kFbxTicksPerSecond = 46'186'158'000;

// One AnimationCurve: keys at tick times, each with what its segment to the next key does.
struct FbxKeyCurve {
  enum class Segment : uint8_t { kConstant, kConstantNext, kLinear, kCubic };
  std::vector<int64_t> times;  // ticks, increasing
  std::vector<double> values;
  std::vector<Segment> segments;  // per key: the segment to the next key
  // Cubic: the key's right slope and the next key's left slope (value per second), and
  // their weights (the fraction of the segment's time each handle reaches; 1/3 unweighted).
  // Empty when no key is cubic (a baked take's linear keys need none of them).
  std::vector<double> right_slopes, next_left_slopes;
  std::vector<double> right_weights, next_left_weights;
};

// The curve's value at `tick`: the first key's before it, the last key's after it.
double EvaluateFbxCurve(const FbxKeyCurve& curve, int64_t tick);
// The same, starting its search at `cursor` (a key index, updated): constant time per call
// when the ticks come in order, as a take's frames do.
double EvaluateFbxCurveFrom(const FbxKeyCurve& curve, int64_t tick, size_t& cursor);

// Euler rotation orders as FBX numbers them (RotationOrder): XYZ, XZY, YZX, YXZ, ZXY, ZYX,
// the first axis applied first.
enum class FbxRotationOrder : int { kXyz = 0, kXzy, kYzx, kYxz, kZxy, kZyx };

// How a node inherits its parent's transform (InheritType), as the FBX SDK names them:
// RSrs, the parent's whole transform (World = ParentWorld * Local, the usual); RrSs, the
// parent's scale applied after the node's rotation (it scales along the parent's axes,
// without shearing the child); Rrs, the parent's own scale not inherited at all (Maya's
// segment scale compensation).
enum class FbxInheritType : int { kRrSs = 0, kRSrs = 1, kRrs = 2 };

struct FbxRigNode {
  int parent = -1;  // an earlier node, or -1
  std::array<double, 3> translation{}, rotation{}, scaling{1, 1, 1};
  std::array<double, 3> pre_rotation{}, post_rotation{};
  std::array<double, 3> rotation_offset{}, rotation_pivot{};
  std::array<double, 3> scaling_offset{}, scaling_pivot{};
  FbxRotationOrder order = FbxRotationOrder::kXyz;
  FbxInheritType inherit = FbxInheritType::kRSrs;
  // Curves (indices into FbxRig::curves, -1: the value above) for Lcl Translation, Lcl
  // Rotation and Lcl Scaling, x y z.
  std::array<int, 3> translation_curves{-1, -1, -1};
  std::array<int, 3> rotation_curves{-1, -1, -1};
  std::array<int, 3> scaling_curves{-1, -1, -1};
};

struct FbxRig {
  std::vector<FbxRigNode> nodes;  // parents before children
  std::vector<FbxKeyCurve> curves;
};

// World positions (the translation of each node's world transform), frame-major:
// frames x nodes x 3, sampled at start_tick + f / fps seconds.
std::vector<double> FbxNodePositions(const FbxRig& rig, int64_t start_tick, double fps,
                                     int64_t frames);

}  // namespace koma

#endif  // KOMA_CORE_FBX_RIG_H_
