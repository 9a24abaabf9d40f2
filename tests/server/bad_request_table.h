// The harness of the bad-request tables (bad_request_test.cc, curves_bad_request_test.cc,
// lip_blink_bad_request_test.cc, grid_bad_request_test.cc, skeletal_grid_test.cc): a table
// file holds only its rows, each a valid request broken one way and the status it must get;
// sending the request and checking the answer is done here, once.
//
//   std::vector<BadRequest<v1::RetimeCurvesRequest>> BadRequests() { return {...rows...}; }
//   class CurvesBadRequestTest
//       : public BadRequestSuite<CurvesBadRequestTest, v1::RetimeCurvesRequest> {
//    public:
//     static server::ServerConfig SuiteConfig() { return InProcessServer::Config(1, 50'000); }
//     static v1::RetimeCurvesRequest ValidRequest() { return MakeCurvesRequest(); }
//   };
//   KOMA_BAD_REQUEST_TABLE(CurvesBadRequestTest, CurvesBadRequestTableTest, BadRequests)
// Tables whose rows are not BadRequest (grid_bad_request_test.cc, skeletal_grid_test.cc) call
// ExpectRefused from their own TEST_P.
#ifndef KOMA_TESTS_SERVER_BAD_REQUEST_TABLE_H_
#define KOMA_TESTS_SERVER_BAD_REQUEST_TABLE_H_

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "tests/server/in_process_server.h"

namespace koma::testing {

// The fields a successful answer fills; a refused call must leave them empty.
inline int AnswerSize(const v1::RetimeSkeletalResponse& r) { return r.source_frames_size(); }
inline int AnswerSize(const v1::RetimeCurvesResponse& r) { return r.curves_size(); }
inline int AnswerSize(const v1::LipBlinkResponse& r) { return r.curves_size(); }

// Sends `request` (with the test deadline) and expects `code`, a status message that holds every
// one of `parts`, and no partial answer. `rpc` names the call in failures, for tables sent
// through two RPCs.
template <typename Request>
void ExpectRefused(v1::Retime::Stub& stub, const Request& request, grpc::StatusCode code,
                   const std::vector<std::string>& parts, const std::string& rpc = "") {
  ResponseOf<Request> response;
  const grpc::Status status = CallRpc(stub, request, &response);
  const std::string where = rpc.empty() ? "" : rpc + ": ";
  EXPECT_EQ(status.error_code(), code) << where << status.error_message();
  for (const std::string& part : parts) {
    EXPECT_THAT(status.error_message(), ::testing::HasSubstr(part)) << where;
  }
  EXPECT_EQ(AnswerSize(response), 0) << where << "a failed call carries no partial answer";
}

// Sends `request` and expects it answered: a table's valid request must be, so that each row's
// refusal comes from the one thing the row breaks.
template <typename Request>
void ExpectAccepted(v1::Retime::Stub& stub, const Request& request) {
  ResponseOf<Request> response;
  const grpc::Status status = CallRpc(stub, request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_GT(AnswerSize(response), 0);
}

// One row: the valid request broken by `mutate` must get `code` and a message holding `message`
// (which names the field and the value).
template <typename Request>
struct BadRequest {
  std::string name;  // the gtest case name
  std::function<void(Request&)> mutate;
  grpc::StatusCode code;
  std::string message;

  friend void PrintTo(const BadRequest& bad, std::ostream* os) { *os << bad.name; }
};

// A table's fixture: one server for all its rows (`Derived::SuiteConfig()`), each row applied
// to `Derived::ValidRequest()`.
template <typename Derived, typename Request>
class BadRequestSuite : public SharedServerTest<Derived, BadRequest<Request>> {
 protected:
  void ExpectTheRowRefused() {
    const BadRequest<Request>& bad = this->GetParam();
    Request request = Derived::ValidRequest();
    bad.mutate(request);
    ExpectRefused(this->stub(), request, bad.code, {bad.message});
  }
};

// Names a parameterised case after its row: INSTANTIATE_TEST_SUITE_P(..., RowName()).
struct RowName {
  template <typename ParamInfo>
  std::string operator()(const ParamInfo& info) const {
    return info.param.name;
  }
};

}  // namespace koma::testing

// Registers a table: one case per row of ROWS() (Table/FIXTURE.AnswersCodeAndNamesTheField/ROW,
// each row refused as it says), and TABLE_TEST.HasAtLeastTwentyRows and
// TABLE_TEST.TheValidRequestIsAccepted (FIXTURE::ValidRequest() answered by a server with
// FIXTURE::SuiteConfig(): each row's refusal comes from what the row breaks).
#define KOMA_BAD_REQUEST_TABLE(FIXTURE, TABLE_TEST, ROWS)                    \
  TEST_P(FIXTURE, AnswersCodeAndNamesTheField) { ExpectTheRowRefused(); }    \
  INSTANTIATE_TEST_SUITE_P(Table, FIXTURE, ::testing::ValuesIn(ROWS()),      \
                           ::koma::testing::RowName());                      \
  TEST(TABLE_TEST, HasAtLeastTwentyRows) { EXPECT_GE(ROWS().size(), 20u); }  \
  TEST(TABLE_TEST, TheValidRequestIsAccepted) {                              \
    ::koma::testing::InProcessServer server(FIXTURE::SuiteConfig());         \
    ::koma::testing::ExpectAccepted(server.stub(), FIXTURE::ValidRequest()); \
  }

#endif  // KOMA_TESTS_SERVER_BAD_REQUEST_TABLE_H_
