// Bad files over the wire: each comes back with the reader's own code and message (the ones
// `koma` prints for the same file, after the path), prefixed with the request field instead of
// the path: "bvh_text: line 5: unknown channel name ...". Tables of broken BVH, motion3.json
// and CSV files, the curve files through both RetimeCurves and LipBlink.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "formats/bvh.h"
#include "formats/curve_csv.h"
#include "formats/motion3.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/replace_once.h"

namespace koma::testing {
namespace {

struct BadFile {
  std::string name;
  std::string text;
};

const char kBvh[] =
    "HIERARCHY\n"
    "ROOT Hips\n"
    "{\n"
    "\tOFFSET 0 0 0\n"
    "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    "\tJOINT Chest\n"
    "\t{\n"
    "\t\tOFFSET 0 5 0\n"
    "\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n"
    "\t\tEnd Site\n"
    "\t\t{\n"
    "\t\t\tOFFSET 0 10 0\n"
    "\t\t}\n"
    "\t}\n"
    "}\n"
    "MOTION\n"
    "Frames: 3\n"
    "Frame Time: 0.0416667\n"
    "0 90 0 0 0 0 10 20 30\n"
    "0 91 0 1 0 0 11 21 31\n"
    "0 92 0 2 0 0 12 22 32\n";

std::vector<BadFile> BadBvhFiles() {
  const std::string good = kBvh;
  return {
      {"empty", ""},
      {"no HIERARCHY", ReplaceOnce(good, "HIERARCHY", "HIERARCHIE")},
      {"unknown channel", ReplaceOnce(good, "Zrotation Xrotation Yrotation\n\t\tEnd",
                                      "Zrot Xrotation Yrotation\n\t\tEnd")},
      {"7 channels", ReplaceOnce(good, "CHANNELS 6", "CHANNELS 7")},
      {"repeated channel", ReplaceOnce(good, "CHANNELS 3 Zrotation Xrotation Yrotation",
                                       "CHANNELS 3 Zrotation Zrotation Yrotation")},
      {"unbalanced braces", ReplaceOnce(good, "\t\t}\n\t}\n", "\t\t}\n")},
      {"duplicate joint", ReplaceOnce(good, "JOINT Chest", "JOINT Hips")},
      {"joint without OFFSET", ReplaceOnce(good, "\t\tOFFSET 0 5 0\n", "")},
      {"End Site with channels", ReplaceOnce(good, "\t\t\tOFFSET 0 10 0\n",
                                             "\t\t\tOFFSET 0 10 0\n\t\t\tCHANNELS 1 Xrotation\n")},
      {"malformed number", ReplaceOnce(good, "0 91 0 1", "0 9x1 0 1")},
      {"nan value", ReplaceOnce(good, "0 91 0 1", "0 nan 0 1")},
      {"too few values", ReplaceOnce(good, "0 92 0 2 0 0 12 22 32\n", "0 92 0 2 0 0 12\n")},
      {"too many values", good + "1 2 3\n"},
      {"negative frames", ReplaceOnce(good, "Frames: 3", "Frames: -3")},
      {"frame time 0", ReplaceOnce(good, "Frame Time: 0.0416667", "Frame Time: 0")},
      {"no MOTION", ReplaceOnce(good, "MOTION", "MOTON")},
  };
}

const char kMotion3[] = R"({
  "Version": 3,
  "Meta": {"Duration": 1, "Fps": 30, "Loop": true, "CurveCount": 1},
  "Curves": [
    {"Target": "Parameter", "Id": "ParamMouthOpenY", "Segments": [0, 0, 0, 0.5, 1, 0, 1, 0]}
  ],
  "UserData": [{"Time": 0.5, "Value": "x"}]
})";

std::vector<BadFile> BadMotion3Files() {
  const std::string good = kMotion3;
  return {
      {"empty", ""},
      {"malformed JSON", ReplaceOnce(good, "\"Version\": 3,", "\"Version\": 3")},
      {"root is an array", "[" + good + "]"},
      {"no Meta", ReplaceOnce(good, "\"Meta\"", "\"Mesa\"")},
      {"Fps 0", ReplaceOnce(good, "\"Fps\": 30", "\"Fps\": 0")},
      {"Fps a string", ReplaceOnce(good, "\"Fps\": 30", "\"Fps\": \"30\"")},
      {"negative Duration", ReplaceOnce(good, "\"Duration\": 1", "\"Duration\": -1")},
      {"Curves not an array", ReplaceOnce(good, "\"Curves\": [", "\"Curves\": 5, \"X\": [")},
      {"unknown Target", ReplaceOnce(good, "\"Target\": \"Parameter\"", "\"Target\": \"Param\"")},
      {"Id a number", ReplaceOnce(good, "\"Id\": \"ParamMouthOpenY\"", "\"Id\": 7")},
      {"segment value a string", ReplaceOnce(good, "[0, 0, 0, 0.5", "[0, \"0\", 0, 0.5")},
      {"unknown segment identifier", ReplaceOnce(good, "[0, 0, 0, 0.5", "[0, 0, 7, 0.5")},
      {"segment cut short", ReplaceOnce(good, "0, 1, 0]}", "0, 1]}")},
      {"UserData Time a string", ReplaceOnce(good, "\"Time\": 0.5", "\"Time\": \"0.5\"")},
      {"too deep", std::string(40, '[') + std::string(40, ']')},
  };
}

const char kCsv[] =
    "frame,ParamMouthOpenY,ParamEyeLOpen\n"
    "0,0,1\n"
    "1,0.5,1\n"
    "2,1,0\n"
    "3,0,1\n";

std::vector<BadFile> BadCsvFiles() {
  const std::string good = kCsv;
  return {
      {"empty", ""},
      {"header not frame", ReplaceOnce(good, "frame,", "time,")},
      {"no curve column", "frame\n0\n1\n"},
      {"empty id", ReplaceOnce(good, ",ParamEyeLOpen", ",")},
      {"duplicate id", ReplaceOnce(good, "ParamEyeLOpen", "ParamMouthOpenY")},
      {"quote in id", ReplaceOnce(good, "ParamEyeLOpen", "Param\"Eye")},
      {"empty line", ReplaceOnce(good, "1,0.5,1\n", "\n1,0.5,1\n")},
      {"extra field", ReplaceOnce(good, "1,0.5,1\n", "1,0.5,1,7\n")},
      {"missing field", ReplaceOnce(good, "1,0.5,1\n", "1,0.5\n")},
      {"frame out of order", ReplaceOnce(good, "2,1,0\n", "5,1,0\n")},
      {"invalid number", ReplaceOnce(good, "1,0.5,1\n", "1,x,1\n")},
      {"nan", ReplaceOnce(good, "1,0.5,1\n", "1,nan,1\n")},
      {"space around a number", ReplaceOnce(good, "1,0.5,1\n", "1, 0.5,1\n")},
      {"no rows", "frame,ParamMouthOpenY\n"},
  };
}

class FileBadRequestTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new InProcessServer(); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static InProcessServer& server() { return *server_; }

 private:
  static inline InProcessServer* server_ = nullptr;
};

// The server's status must be the reader's, prefixed with `field`.
void ExpectReaderError(const grpc::Status& status, const absl::Status& reader,
                       const std::string& field, bool with_line) {
  ASSERT_FALSE(reader.ok()) << "the test's file is not bad";
  EXPECT_EQ(static_cast<int>(status.error_code()), static_cast<int>(reader.code()));
  EXPECT_EQ(status.error_message(), field + ": " + std::string(reader.message()));
  if (with_line) {
    EXPECT_NE(status.error_message().find("line "), std::string::npos) << status.error_message();
  }
}

TEST_F(FileBadRequestTest, BadBvhFilesGetTheReadersErrorNamingBvhText) {
  const std::vector<BadFile> files = BadBvhFiles();
  ASSERT_GE(files.size(), 10u);
  for (const BadFile& file : files) {
    SCOPED_TRACE(file.name);
    v1::RetimeSkeletalRequest request;
    request.set_bvh_text(file.text);
    v1::RetimeSkeletalResponse response;
    const grpc::Status status = CallRpc(server().stub(), request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    ExpectReaderError(status, formats::ParseBvh(file.text).status(), "bvh_text",
                      /*with_line=*/true);
  }
}

void ExpectCurveFileErrors(InProcessServer& server, const std::vector<BadFile>& files, bool csv) {
  ASSERT_GE(files.size(), 10u);
  const std::string field = csv ? "csv_text" : "motion3_json";
  for (const BadFile& file : files) {
    SCOPED_TRACE(file.name);
    const absl::Status reader = csv ? formats::ParseCurveCsv(file.text, 30).status()
                                    : formats::ParseMotion3(file.text).status();
    v1::RetimeCurvesRequest curves;
    v1::LipBlinkRequest lip;
    if (csv) {
      curves.set_csv_text(file.text);
      lip.set_csv_text(file.text);
    } else {
      curves.set_motion3_json(file.text);
      lip.set_motion3_json(file.text);
    }
    v1::RetimeCurvesResponse curves_response;
    v1::LipBlinkResponse lip_response;
    const grpc::Status curves_status = CallRpc(server.stub(), curves, &curves_response);
    const grpc::Status lip_status = CallRpc(server.stub(), lip, &lip_response);
    EXPECT_NE(curves_status.error_code(), grpc::StatusCode::OK);
    ExpectReaderError(curves_status, reader, field, /*with_line=*/csv);
    ExpectReaderError(lip_status, reader, field, /*with_line=*/csv);
  }
}

TEST_F(FileBadRequestTest, BadMotion3FilesGetTheReadersErrorNamingMotion3Json) {
  ExpectCurveFileErrors(server(), BadMotion3Files(), /*csv=*/false);
}

TEST_F(FileBadRequestTest, BadCsvFilesGetTheReadersErrorNamingCsvText) {
  ExpectCurveFileErrors(server(), BadCsvFiles(), /*csv=*/true);
}

// The untouched bases of the tables are good files: each case breaks exactly one thing.
TEST_F(FileBadRequestTest, TheTablesBaseFilesAreAnswered) {
  v1::RetimeSkeletalRequest skeletal;
  skeletal.set_bvh_text(kBvh);
  v1::RetimeSkeletalResponse skeletal_response;
  EXPECT_TRUE(CallRpc(server().stub(), skeletal, &skeletal_response).ok());
  v1::LipBlinkRequest lip;
  lip.set_motion3_json(kMotion3);
  v1::LipBlinkResponse lip_response;
  const grpc::Status lip_status = CallRpc(server().stub(), lip, &lip_response);
  EXPECT_TRUE(lip_status.ok()) << lip_status.error_message();
  v1::RetimeCurvesRequest curves;
  curves.set_csv_text(kCsv);
  v1::RetimeCurvesResponse curves_response;
  const grpc::Status curves_status = CallRpc(server().stub(), curves, &curves_response);
  EXPECT_TRUE(curves_status.ok()) << curves_status.error_message();
  EXPECT_FALSE(curves_response.csv_text().empty());
}

}  // namespace
}  // namespace koma::testing
