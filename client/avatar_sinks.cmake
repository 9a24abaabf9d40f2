# koma live's avatar links (included by client/CMakeLists.txt after koma_client_lib): VMC over
# OSC through Debian's liblo (liblo-dev, pkg-config "liblo") and VTube Studio's WebSocket API
# through Debian's civetweb client (libcivetweb-dev, no pkg-config file: found by name).
pkg_check_modules(LIBLO REQUIRED IMPORTED_TARGET liblo)
find_path(CIVETWEB_INCLUDE_DIR civetweb.h REQUIRED)
find_library(CIVETWEB_LIBRARY civetweb REQUIRED)

add_library(koma_avatar_sinks
  avatar_levels.cc
  avatar_sink_flags.cc
  vmc_sink.cc
  vts_messages.cc
  vtube_studio_sink.cc
  websocket_client.cc
)
target_include_directories(koma_avatar_sinks PUBLIC ${PROJECT_SOURCE_DIR})
target_include_directories(koma_avatar_sinks SYSTEM PRIVATE ${CIVETWEB_INCLUDE_DIR})
target_compile_options(koma_avatar_sinks PRIVATE ${KOMA_WARNINGS})
target_link_libraries(koma_avatar_sinks PUBLIC koma_proto CLI11::CLI11 nlohmann_json::nlohmann_json
  absl::status absl::statusor absl::strings PRIVATE PkgConfig::LIBLO ${CIVETWEB_LIBRARY} Threads::Threads)
target_link_libraries(koma_client_lib PUBLIC koma_avatar_sinks)
