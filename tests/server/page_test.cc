// The page's file jobs (client/file_job.h, server/page_options.h, server/page_routes.h): a job
// writes the bytes the CLI writes from files on disk with the same command line; the query's
// options are checked; the routes answer with the page's CSP, errors as JSON naming the field.
#include <gtest/gtest.h>
#include <pthread.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "absl/strings/escaping.h"
#include "client/channel.h"
#include "client/cli.h"
#include "client/file_job.h"
#include "server/page_options.h"
#include "server/page_routes.h"
#include "tests/server/in_process_server.h"

namespace koma {
namespace {

namespace fs = std::filesystem;

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// The CLI on real files: `line` run in a fresh folder holding the input, its call on
// `channel`. The files it wrote, by name.
std::map<std::string, std::string> RunCliOnDisk(const std::vector<std::string>& line,
                                                const client::FileJob& job,
                                                const std::shared_ptr<grpc::Channel>& channel) {
  const fs::path folder = fs::temp_directory_path() / ("koma-page-test-" + std::to_string(getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  std::ofstream(folder / job.input_name, std::ios::binary) << job.input;
  const fs::path before = fs::current_path();
  fs::current_path(folder);  // the names on the line are bare, as the job's
  client::KomaCommandLine parsed;
  int code = client::ParseCommandLine(line, &parsed);
  if (code < 0) {
    const client::ScopedRetimeChannel call(channel);
    code = client::RunCommandLine(parsed);
  }
  fs::current_path(before);
  EXPECT_EQ(code, 0);
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name != job.input_name) files[name] = ReadBytes(entry.path());
  }
  fs::remove_all(folder);
  return files;
}

struct JobCase {
  const char* command;
  const char* file;  // under samples/ or tests/testdata/
  std::vector<std::string> options;
  std::vector<std::string> roles;  // the outputs the job must write
};

void PrintTo(const JobCase& c, std::ostream* out) { *out << c.command << " " << c.file; }

class FileJobTest : public ::testing::TestWithParam<JobCase> {};

TEST_P(FileJobTest, WritesTheCliBytes) {
  const JobCase& c = GetParam();
  testing::InProcessServer server;
  const std::shared_ptr<grpc::Channel> channel = server.server().InProcessChannel();
  fs::path path = fs::path(KOMA_SAMPLES_DIR) / c.file;
  if (!fs::exists(path)) path = fs::path(KOMA_TESTDATA_DIR) / c.file;
  client::FileJob job;
  job.command = c.command;
  job.input_name = path.filename().string();
  job.input = ReadBytes(path);
  ASSERT_FALSE(job.input.empty()) << path;
  job.options = c.options;
  absl::StatusOr<client::FileJobResult> result = client::RunFileJob(job, channel);
  ASSERT_TRUE(result.ok()) << result.status();
  ASSERT_EQ(result->exit_code, 0) << result->messages;
  EXPECT_EQ(result->summary.value("status", ""), "ok");
  std::vector<std::string> roles;
  for (const auto& file : result->files) roles.push_back(file.role);
  EXPECT_EQ(roles, c.roles);

  const std::map<std::string, std::string> cli = RunCliOnDisk(result->command_line, job, channel);
  ASSERT_EQ(cli.size(), result->files.size());
  for (const client::FileJobFile& file : result->files) {
    ASSERT_TRUE(cli.count(file.name)) << file.name;
    EXPECT_FALSE(file.bytes.empty()) << file.name;
    EXPECT_TRUE(cli.at(file.name) == file.bytes) << file.name << " differs from the CLI's";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Formats, FileJobTest,
    ::testing::Values(
        JobCase{"skeletal", "pitch.bvh", {"--preset", "twos"}, {"result", "timing", "xdts", "report"}},
        JobCase{"skeletal", "wave.glb", {"--omit", "2"}, {"result", "timing", "xdts", "report"}},
        JobCase{"curves", "arm_head.motion3.json", {"--on", "3", "--tame", "1.5"},
                {"result", "timing", "xdts", "report"}},
        JobCase{"curves", "spine/hero-4.2.json", {"--preset", "threes"},
                {"result", "timing", "xdts", "report"}},
        JobCase{"lipblink", "talk_blink.motion3.json", {"--seed", "7"}, {"result", "xdts", "report"}},
        JobCase{"lipblink", "voice.flac", {"--preset", "subtle", "--auto-blink", "3"},
                {"result", "xdts", "report"}}),
    [](const ::testing::TestParamInfo<JobCase>& info) {
      std::string name = std::string(info.param.command) + "_" + info.param.file;
      for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      }
      return name;
    });

TEST(FileJob, AFailureIsKomasMessageAndNoFiles) {
  testing::InProcessServer server;
  client::FileJob job{"curves", "bad.motion3.json", "{\"Version\": 3", {"--on", "2"}};
  absl::StatusOr<client::FileJobResult> result =
      client::RunFileJob(job, server.server().InProcessChannel());
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->exit_code, 1);
  EXPECT_NE(result->messages.find("bad.motion3.json"), std::string::npos) << result->messages;
  EXPECT_TRUE(result->files.empty());
  job.options = {"--tame", "0.5"};
  job.input = ReadBytes(fs::path(KOMA_SAMPLES_DIR) / "arm_head.motion3.json");
  job.input_name = "arm_head.motion3.json";
  result = client::RunFileJob(job, server.server().InProcessChannel());
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->exit_code, 2);
  EXPECT_NE(result->messages.find("--tame: 0.5 is out of range"), std::string::npos)
      << result->messages;
}

TEST(FileJob, ReadsNothingButItsFile) {
  // A name that is a path is refused; an option naming another file finds nothing on disk.
  client::FileJob job{"skeletal", "../etc/passwd.bvh", "x", {}};
  EXPECT_FALSE(client::FileJobCommandLine(job).ok());
  job.input_name = "-";
  EXPECT_FALSE(client::FileJobCommandLine(job).ok());
  testing::InProcessServer server;
  job = {"lipblink", "talk_blink.motion3.json",
         ReadBytes(fs::path(KOMA_SAMPLES_DIR) / "talk_blink.motion3.json"),
         {"--audio", std::string(KOMA_SAMPLES_DIR) + "/voice.flac"}};
  absl::StatusOr<client::FileJobResult> result =
      client::RunFileJob(job, server.server().InProcessChannel());
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->exit_code, 1);
  EXPECT_NE(result->messages.find("cannot read"), std::string::npos) << result->messages;
}

TEST(FileJob, InspectsEachFormat) {
  const auto inspect = [](const char* file) {
    fs::path path = fs::path(KOMA_SAMPLES_DIR) / file;
    return client::InspectFile(path.filename().string(), ReadBytes(path));
  };
  nlohmann::json bvh = inspect("pitch.bvh");
  EXPECT_EQ(bvh["format"], "bvh");
  EXPECT_GT(bvh["frames"].get<int>(), 10);
  EXPECT_GT(bvh["joints"].get<int>(), 1);
  EXPECT_EQ(bvh["commands"][0]["command"], "skeletal");
  nlohmann::json motion3 = inspect("arm_head.motion3.json");
  EXPECT_EQ(motion3["format"], "motion3");
  EXPECT_GT(motion3["curves"].size(), 0u);
  EXPECT_EQ(motion3["commands"].size(), 2u);  // curves and lipblink
  EXPECT_EQ(inspect("hero.json")["format"], "spine");
  EXPECT_GT(inspect("hero.json")["animations"].size(), 0u);
  EXPECT_EQ(inspect("wave.glb")["format"], "gltf");
  nlohmann::json voice = inspect("voice.flac");
  EXPECT_EQ(voice["format"], "audio");
  EXPECT_GT(voice["seconds"].get<double>(), 1.0);
  EXPECT_EQ(voice["commands"][0]["flag"], "--audio");
  nlohmann::json bad = client::InspectFile("x.bvh", "HIERARCHY\nROOT");
  EXPECT_EQ(bad["format"], "bvh");
  EXPECT_TRUE(bad.contains("error"));
}

TEST(PageOptions, TurnsTheQueryIntoFlags) {
  absl::StatusOr<client::FileJob> job = server::PageJobFromQuery(
      "command=curves&name=arm%20head.motion3.json&preset=twos&tame=1.5&tsume=&xdts=0", "BODY");
  ASSERT_TRUE(job.ok()) << job.status();
  EXPECT_EQ(job->command, "curves");
  EXPECT_EQ(job->input_name, "arm head.motion3.json");
  EXPECT_EQ(job->input, "BODY");
  EXPECT_EQ(job->options, (std::vector<std::string>{"--preset", "twos", "--tame", "1.5"}));
  EXPECT_FALSE(job->xdts);
  EXPECT_TRUE(job->report);
}

TEST(PageOptions, RefusesWhatTheCommandDoesNotTake) {
  const auto error = [](const char* query) {
    absl::StatusOr<client::FileJob> job = server::PageJobFromQuery(query, "");
    return job.ok() ? std::string("ok") : std::string(job.status().message());
  };
  EXPECT_EQ(error("command=skeletal"), "the query needs command=skeletal|curves|lipblink and name=FILE");
  EXPECT_EQ(error("command=skeletal&name=a.bvh&server=x:1"), "unknown parameter \"server\"");
  EXPECT_EQ(error("command=skeletal&name=a.bvh&tame=2"),
            "tame: koma skeletal has no --tame (it is for koma curves)");
  EXPECT_EQ(error("command=skeletal&name=a.bvh&omit=-1"), "omit=-1: must be a whole number");
  EXPECT_EQ(error("command=curves&name=a.csv&preset=fast"),
            "preset=fast: must be one of twos, threes, snappy, subtle");
  EXPECT_EQ(error("command=curves&name=a.csv&report=yes"), "report=yes: give 0 or 1");
  EXPECT_EQ(error("command=curves&name=a.csv&on=2&on=3"), "query parameter on given twice");
}

TEST(PageRoutes, ServeTheAssetsAndJobs) {
  testing::InProcessServer grpc_server;
  server::HttpServerConfig config;
  config.port = 0;
  absl::StatusOr<std::unique_ptr<server::HttpServer>> http = server::HttpServer::Start(config);
  ASSERT_TRUE(http.ok()) << http.status();
  server::RegisterPageRoutes(**http, grpc_server.server().InProcessChannel());
  const auto respond = [&](const char* method, const char* path, std::string query,
                           std::string body) {
    server::HttpRequest request;
    request.method = method;
    request.path = path;
    request.query = std::move(query);
    request.body = std::move(body);
    return (*http)->Respond(request);
  };
  const auto header = [](const server::HttpResponse& response, const char* name) {
    std::string value;
    for (const auto& [key, v] : response.headers) {
      if (key == name) value = v;
    }
    return value;
  };
  server::HttpResponse page = respond("GET", "/", "", "");
  EXPECT_EQ(page.status, 200);
  EXPECT_NE(page.body.find("<input type=\"file\" id=\"file\""), std::string::npos);
  EXPECT_EQ(header(page, "Content-Security-Policy"), server::kPageContentSecurityPolicy);
  EXPECT_EQ(respond("GET", "/page.js", "", "").status, 200);
  server::HttpResponse frame = respond("GET", "/page/report-frame.html", "", "");
  EXPECT_EQ(header(frame, "Content-Security-Policy"), server::kReportFrameContentSecurityPolicy);
  EXPECT_EQ(respond("GET", "/index.html/../etc/passwd", "", "").status, 404);

  server::HttpResponse bad = respond("POST", "/page/run", "command=curves&name=a.csv&tame=x", "");
  EXPECT_EQ(bad.status, 400);
  EXPECT_EQ(nlohmann::json::parse(bad.body)["error"]["message"], "tame=x: must be a number");

  const std::string bvh = ReadBytes(fs::path(KOMA_SAMPLES_DIR) / "pitch.bvh");
  server::HttpResponse run = respond("POST", "/page/run", "command=skeletal&name=pitch.bvh&preset=twos", bvh);
  ASSERT_EQ(run.status, 200) << run.body.substr(0, 500);
  const nlohmann::json answer = nlohmann::json::parse(run.body);
  EXPECT_EQ(answer["command"],
            "koma skeletal pitch.bvh -o pitch_anime.bvh --timing pitch_timing.csv --xdts "
            "pitch.xdts --report pitch_report.html --preset twos");
  ASSERT_EQ(answer["files"].size(), 4u);
  std::string result;
  ASSERT_TRUE(absl::Base64Unescape(answer["files"][0]["base64"].get<std::string>(), &result));
  EXPECT_EQ(result.substr(0, 9), "HIERARCHY");

  server::HttpResponse failed = respond("POST", "/page/run", "command=skeletal&name=x.bvh", "MOTION");
  EXPECT_EQ(failed.status, 400);
  EXPECT_EQ(nlohmann::json::parse(failed.body)["exit_code"], 1);
}

// server.Respond(request) on a thread with a 100 KiB stack, as civetweb's.
server::HttpResponse RespondOnSmallStack(const server::HttpServer& server,
                                         const server::HttpRequest& request) {
  struct Call {
    const server::HttpServer* server;
    const server::HttpRequest* request;
    server::HttpResponse response;
  } call{&server, &request, {}};
  pthread_attr_t attributes;
  pthread_attr_init(&attributes);
  pthread_attr_setstacksize(&attributes, 100 * 1024);
  pthread_t thread;
  const int error = pthread_create(
      &thread, &attributes,
      [](void* p) -> void* {
        auto* c = static_cast<Call*>(p);
        c->response = c->server->Respond(*c->request);
        return nullptr;
      },
      &call);
  pthread_attr_destroy(&attributes);
  EXPECT_EQ(error, 0);
  if (error == 0) pthread_join(thread, nullptr);
  return call.response;
}

TEST(PageRoutes, AnswerOnCivetwebSizedStacks) {
  // A job, and truncated samples, deep JSON and noise under every name and command: each
  // answered (200, or 400 with JSON), never a crash, on a thread with a 100 KiB stack like
  // civetweb's. (This does not reproduce koma_server's overflow of a civetweb thread in a
  // job's gRPC call: the job passes here even run inline; web.page, on the real server, does.)
  testing::InProcessServer grpc_server;
  server::HttpServerConfig config;
  config.port = 0;
  absl::StatusOr<std::unique_ptr<server::HttpServer>> http = server::HttpServer::Start(config);
  ASSERT_TRUE(http.ok()) << http.status();
  server::RegisterPageRoutes(**http, grpc_server.server().InProcessChannel());
  std::vector<std::pair<std::string, std::string>> files;  // name, bytes
  for (const char* sample : {"pitch.bvh", "arm_head.motion3.json", "hero.json", "wave.glb",
                             "voice.flac", "huesitos.fbx"}) {
    const std::string bytes = ReadBytes(fs::path(KOMA_SAMPLES_DIR) / sample);
    files.emplace_back(sample, bytes.substr(0, bytes.size() / 2));
  }
  files.emplace_back("deep.motion3.json", std::string(200000, '[') + std::string(200000, ']'));
  files.emplace_back("deep.json", "{\"skeleton\":" + std::string(200000, '['));
  files.emplace_back("deep.gltf", "{\"asset\":" + std::string(200000, '['));
  files.emplace_back("noise.wav", std::string("RIFF\xff\xff\xff\x7fWAVEfmt ") + std::string(64, '\x01'));
  // A whole job too.
  server::HttpRequest good;
  good.method = "POST";
  good.path = "/page/run";
  good.query = "command=skeletal&name=pitch.bvh";
  good.body = ReadBytes(fs::path(KOMA_SAMPLES_DIR) / "pitch.bvh");
  EXPECT_EQ(RespondOnSmallStack(**http, good).status, 200);
  for (const auto& [name, bytes] : files) {
    for (const char* command : {"skeletal", "curves", "lipblink"}) {
      server::HttpRequest request;
      request.method = "POST";
      request.path = "/page/run";
      request.query = std::string("command=") + command + "&name=" + name;
      request.body = bytes;
      const server::HttpResponse run = RespondOnSmallStack(**http, request);
      EXPECT_EQ(run.status, 400) << name << " " << command << ": " << run.body.substr(0, 300);
      EXPECT_TRUE(nlohmann::json::accept(run.body)) << name;
    }
    server::HttpRequest inspect;
    inspect.method = "POST";
    inspect.path = "/page/inspect";
    inspect.query = "name=" + name;
    inspect.body = bytes;
    const server::HttpResponse info = RespondOnSmallStack(**http, inspect);
    EXPECT_EQ(info.status, 200) << name;
    EXPECT_TRUE(nlohmann::json::parse(info.body).contains("format")) << name;
  }
}

}  // namespace
}  // namespace koma
