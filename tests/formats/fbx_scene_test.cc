// An FBX file's take as a rig (formats/fbx_scene.h) and its evaluation (core/fbx_rig.h), on the
// real files of tests/testdata/fbx and on curves and transforms made here.
#include "formats/fbx_scene.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "core/fbx_rig.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

FbxDocument ReadTestFbx(const std::string& name) {
  std::ifstream in(std::string(KOMA_TESTDATA_DIR) + "/fbx/" + name, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  absl::StatusOr<FbxDocument> document = ReadFbx(bytes.str());
  EXPECT_TRUE(document.ok()) << document.status();
  return *std::move(document);
}

TEST(FbxSceneTest, BlenderFilesHaveTheirBonesTakeAndRate) {
  struct Expected {
    const char* file;
    double fps;
    size_t limb_nodes;
    const char* take;
  };
  for (const Expected& e :
       {Expected{"assimp_animation_with_skeleton.fbx", 24.0, 16, "Armature|ArmatureAction"},
        Expected{"assimp_huesitos.fbx", 25.0, 11, "Armature|Action"}}) {
    ASSERT_OK_AND_ASSIGN(const FbxTakeRig rig, ReadFbxTakeRig(ReadTestFbx(e.file), ""));
    EXPECT_EQ(rig.fps, e.fps) << e.file;
    EXPECT_EQ(rig.take.name, e.take);
    EXPECT_EQ(std::count(rig.types.begin(), rig.types.end(), "LimbNode"),
              static_cast<std::ptrdiff_t>(e.limb_nodes))
        << e.file;
    EXPECT_FALSE(rig.rig.curves.empty());
    for (size_t i = 0; i < rig.rig.nodes.size(); ++i) {
      EXPECT_LT(rig.rig.nodes[i].parent, static_cast<int>(i)) << "parents first";
      // Each model says InheritType 1 (RSrs) over its template's 0.
      EXPECT_EQ(rig.rig.nodes[i].inherit, FbxInheritType::kRSrs) << rig.names[i];
    }
    const std::vector<double> positions = FbxNodePositions(rig.rig, rig.take.start, rig.fps, 10);
    ASSERT_EQ(positions.size(), 10 * rig.rig.nodes.size() * 3);
    for (double p : positions) EXPECT_TRUE(std::isfinite(p));
  }
}

// Maya's three layers: the base layer is what is read (take.layers says how many there are).
TEST(FbxSceneTest, MayaTakeWithLayers) {
  ASSERT_OK_AND_ASSIGN(const FbxTakeRig rig,
                       ReadFbxTakeRig(ReadTestFbx("ufbx_maya_anim_layers_7500_binary.fbx"), ""));
  EXPECT_EQ(rig.fps, 24.0);
  EXPECT_EQ(rig.take.name, "Take 001");
  EXPECT_EQ(rig.take.layers, 3);
  ASSERT_EQ(rig.names, std::vector<std::string>({"pCube1"}));
  EXPECT_EQ(rig.rig.nodes[0].scaling, (std::array<double, 3>{2, 2, 2}));
}

TEST(FbxSceneTest, ATakeThatIsNotThereNamesTheOnesThatAre) {
  EXPECT_THAT(ReadFbxTakeRig(ReadTestFbx("assimp_huesitos.fbx"), "Run").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("take \"Run\": not in the file (it has \"Armature|Action\")")));
}

// A retimed take written back: frame k of the new file shows the source at the time asked for
// (here each frame holds the even frame before it: on twos), keys are constant, every other
// node as it was, and the take ends at the new length.
TEST(FbxWriteRetimedTest, EachOutputFrameShowsTheSourceTimeItWasGiven) {
  for (const char* name : {"assimp_animation_with_skeleton.fbx", "assimp_huesitos.fbx"}) {
    const FbxDocument document = ReadTestFbx(name);
    ASSERT_OK_AND_ASSIGN(const FbxTakeRig rig, ReadFbxTakeRig(document, ""));
    const int frames = 20;
    std::vector<int64_t> ticks(frames);
    for (int k = 0; k < frames; ++k) {
      ticks[k] = rig.take.start + std::llround((k / 2 * 2) * kFbxTicksPerSecond / rig.fps);
    }
    ASSERT_OK_AND_ASSIGN(const std::string written, WriteFbxRetimed(document, rig, ticks, rig.fps));
    ASSERT_OK_AND_ASSIGN(const FbxDocument again, ReadFbx(written));
    ASSERT_OK_AND_ASSIGN(const FbxTakeRig retimed, ReadFbxTakeRig(again, ""));
    ASSERT_EQ(retimed.names, rig.names);
    EXPECT_EQ(retimed.take.stop,
              rig.take.start + std::llround((frames - 1) * kFbxTicksPerSecond / rig.fps));
    const std::vector<double> source = FbxNodePositions(rig.rig, rig.take.start, rig.fps, frames);
    const std::vector<double> out =
        FbxNodePositions(retimed.rig, retimed.take.start, retimed.fps, frames);
    const size_t n = rig.names.size() * 3;
    for (int k = 0; k < frames; ++k) {
      for (size_t i = 0; i < n; ++i) {
        // KeyValueFloat holds floats: within a float's precision of the source.
        EXPECT_NEAR(out[k * n + i], source[(k / 2 * 2) * n + i],
                    1e-4 * (1 + std::fabs(source[(k / 2 * 2) * n + i])))
            << name << " frame " << k;
      }
    }
    for (const FbxKeyCurve& curve : retimed.rig.curves) {
      ASSERT_EQ(curve.times.size(), static_cast<size_t>(frames));
      for (FbxKeyCurve::Segment segment : curve.segments) {
        EXPECT_EQ(segment, FbxKeyCurve::Segment::kConstant);
      }
    }
    // The rest of the file: the same models, geometry and connections.
    const FbxNode* geometry_before = nullptr;
    const FbxNode* geometry_after = nullptr;
    for (const FbxNode& node : document.nodes) {
      if (node.name == "Objects") geometry_before = node.Child("Geometry");
    }
    for (const FbxNode& node : again.nodes) {
      if (node.name == "Objects") geometry_after = node.Child("Geometry");
    }
    ASSERT_NE(geometry_after, nullptr);
    EXPECT_EQ(geometry_after->property_bytes, geometry_before->property_bytes);
  }
}

FbxKeyCurve TwoKeys(FbxKeyCurve::Segment segment) {
  FbxKeyCurve curve;
  curve.times = {0, kFbxTicksPerSecond};
  curve.values = {0.0, 10.0};
  curve.segments = {segment, segment};
  curve.right_slopes = {0.0, 0.0};
  curve.next_left_slopes = {0.0, 0.0};
  curve.right_weights = {1.0 / 3, 1.0 / 3};
  curve.next_left_weights = {1.0 / 3, 1.0 / 3};
  return curve;
}

TEST(FbxRigTest, CurvesEvaluateAsTheirFlagsSay) {
  const int64_t half = kFbxTicksPerSecond / 2;
  EXPECT_DOUBLE_EQ(EvaluateFbxCurve(TwoKeys(FbxKeyCurve::Segment::kConstant), half), 0.0);
  EXPECT_DOUBLE_EQ(EvaluateFbxCurve(TwoKeys(FbxKeyCurve::Segment::kConstantNext), half), 10.0);
  EXPECT_DOUBLE_EQ(EvaluateFbxCurve(TwoKeys(FbxKeyCurve::Segment::kLinear), half), 5.0);
  // Flat tangents: the smoothstep, 10 * (3 u^2 - 2 u^3); at a quarter 10 * 0.15625.
  FbxKeyCurve cubic = TwoKeys(FbxKeyCurve::Segment::kCubic);
  EXPECT_NEAR(EvaluateFbxCurve(cubic, half), 5.0, 1e-9);
  EXPECT_NEAR(EvaluateFbxCurve(cubic, kFbxTicksPerSecond / 4), 1.5625, 1e-9);
  // Slopes of 10 a second at both ends: the straight line.
  cubic.right_slopes = {10.0, 0.0};
  cubic.next_left_slopes = {10.0, 0.0};
  EXPECT_NEAR(EvaluateFbxCurve(cubic, kFbxTicksPerSecond / 4), 2.5, 1e-9);
  // Before the first key and after the last: their values.
  EXPECT_DOUBLE_EQ(EvaluateFbxCurve(cubic, -5), 0.0);
  EXPECT_DOUBLE_EQ(EvaluateFbxCurve(cubic, 3 * kFbxTicksPerSecond), 10.0);
}

TEST(FbxRigTest, TheTransformChainWithPreRotationAndPivots) {
  FbxRig rig;
  FbxRigNode root;
  root.translation = {1, 0, 0};
  root.pre_rotation = {0, 0, 90};  // turns the child's offset from +x to +y
  FbxRigNode child;
  child.parent = 0;
  child.translation = {2, 0, 0};
  FbxRigNode pivoted;
  pivoted.parent = 0;
  pivoted.rotation = {0, 0, 180};
  pivoted.rotation_pivot = {1, 0, 0};  // rotating about x = 1 moves the origin to x = 2
  rig.nodes = {root, child, pivoted};
  const std::vector<double> p = FbxNodePositions(rig, 0, 30.0, 1);
  EXPECT_NEAR(p[0], 1, 1e-12);
  EXPECT_NEAR(p[3], 1, 1e-12);  // child: 1 + R(90)(2, 0, 0) = (1, 2, 0)
  EXPECT_NEAR(p[4], 2, 1e-12);
  EXPECT_NEAR(p[6], 1, 1e-12);  // pivoted: R(90) of (2, 0, 0) = (0, 2, 0), plus (1, 0, 0)
  EXPECT_NEAR(p[7], 2, 1e-12);
}

// A parent scaled (2, 1, 1) and turned 90 degrees about z, a child turned 90 more, and two
// grandchildren one unit along the child's x and y: where they land says how the child
// inherited the parent's scale (worked by hand from the SDK's three definitions).
TEST(FbxRigTest, InheritTypesPlaceTheGrandchildrenAsTheSdkDefinesThem) {
  struct Case {
    FbxInheritType type;
    std::array<double, 3> along_x, along_y;
  };
  const Case cases[] = {
      // RSrs: the child's axes sheared by the parent's world: x -> (-1, 0), y -> (0, -2).
      {FbxInheritType::kRSrs, {-1, 2, 0}, {0, 0, 0}},
      // RrSs: the parent's scale after the child's rotation: x -> (-2, 0), y -> (0, -1).
      {FbxInheritType::kRrSs, {-2, 2, 0}, {0, 1, 0}},
      // Rrs: the parent's own scale dropped: x -> (-1, 0), y -> (0, -1).
      {FbxInheritType::kRrs, {-1, 2, 0}, {0, 1, 0}},
  };
  for (const Case& c : cases) {
    FbxRig rig;
    FbxRigNode root;
    root.scaling = {2, 1, 1};
    root.rotation = {0, 0, 90};
    FbxRigNode child;
    child.parent = 0;
    child.translation = {1, 0, 0};
    child.rotation = {0, 0, 90};
    child.inherit = c.type;
    FbxRigNode along_x;
    along_x.parent = 1;
    along_x.translation = {1, 0, 0};
    FbxRigNode along_y = along_x;
    along_y.translation = {0, 1, 0};
    rig.nodes = {root, child, along_x, along_y};
    const std::vector<double> p = FbxNodePositions(rig, 0, 30.0, 1);
    const int type = static_cast<int>(c.type);
    EXPECT_NEAR(p[3], 0, 1e-12) << type;  // the child: the parent's world of (1, 0, 0)
    EXPECT_NEAR(p[4], 2, 1e-12) << type;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(p[6 + a], c.along_x[static_cast<size_t>(a)], 1e-12) << type << " axis " << a;
      EXPECT_NEAR(p[9 + a], c.along_y[static_cast<size_t>(a)], 1e-12) << type << " axis " << a;
    }
  }
}

}  // namespace
}  // namespace koma::formats
