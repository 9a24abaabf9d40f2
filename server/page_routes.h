// The page koma_server serves on its HTTP port (docs/page.md): GET / and its assets (web/,
// compiled in), and two POST endpoints that take a file's bytes as the body:
//   /page/inspect?name=FILE            what the file is (client::InspectFile), JSON
//   /page/run?command=C&name=FILE&...  the file through `koma C` (server/page_options.h) on
//                                      the server's in-process channel: JSON with the files
//                                      koma writes (base64), its command line and summary
// and GET /page/report-frame.html, the sandboxed frame the page shows a report in.
#ifndef KOMA_SERVER_PAGE_ROUTES_H_
#define KOMA_SERVER_PAGE_ROUTES_H_

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string_view>

#include "server/http_server.h"

namespace koma::server {

// The embedded file web/`name` ("index.html"); empty when there is none (generated at build
// time by client/report/embed_templates.cmake).
std::string_view PageAsset(std::string_view name);

// The Content-Security-Policy of the page: its own scripts, styles and frame only, requests
// to its own origin only.
inline constexpr char kPageContentSecurityPolicy[] =
    "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
    "connect-src 'self'; frame-src 'self'; frame-ancestors 'none'; base-uri 'none'; "
    "form-action 'none'";

// The report frame's: a sandbox with an opaque origin (nothing of the page's reachable), the
// inline scripts and styles of the report it is handed, nothing from the network.
inline constexpr char kReportFrameContentSecurityPolicy[] =
    "sandbox allow-scripts; default-src 'none'; script-src 'unsafe-inline'; "
    "style-src 'unsafe-inline'; img-src data: blob:; media-src data: blob:; "
    "frame-ancestors 'self'; base-uri 'none'; form-action 'none'";

// Registers the page's routes on `http`; jobs call the service on `channel`.
void RegisterPageRoutes(HttpServer& http, std::shared_ptr<grpc::Channel> channel);

}  // namespace koma::server

#endif  // KOMA_SERVER_PAGE_ROUTES_H_
