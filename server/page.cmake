# The page koma_server serves on its HTTP port (server/page_routes.h, docs/page.md): web/'s
# files compiled in (the report's embedding step, client/report/embed_templates.cmake), and the
# file jobs, which run the CLI's own commands (client/file_job.h): so this library, and only
# koma_server through it, links the client library. koma_server_lib stays client-free.
set(KOMA_PAGE_ASSETS
  ${PROJECT_SOURCE_DIR}/web/index.html
  ${PROJECT_SOURCE_DIR}/web/page.css
  ${PROJECT_SOURCE_DIR}/web/page.js
  ${PROJECT_SOURCE_DIR}/web/report-frame.html
)
set(page_assets_cc ${CMAKE_CURRENT_BINARY_DIR}/page_assets.cc)
add_custom_command(
  OUTPUT ${page_assets_cc}
  COMMAND ${CMAKE_COMMAND} -DOUT=${page_assets_cc} "-DFILES=${KOMA_PAGE_ASSETS}"
          -DNAMESPACE=koma::server -DHEADER=server/page_routes.h -DFUNCTION=PageAsset
          -DSOURCE_NOTE=web/
          -P ${PROJECT_SOURCE_DIR}/client/report/embed_templates.cmake
  DEPENDS ${KOMA_PAGE_ASSETS} ${PROJECT_SOURCE_DIR}/client/report/embed_templates.cmake
  COMMENT "Embedding the page's assets"
  VERBATIM)

add_library(koma_page_lib ${page_assets_cc} page_options.cc page_routes.cc)
target_include_directories(koma_page_lib PUBLIC ${PROJECT_SOURCE_DIR})
target_compile_options(koma_page_lib PRIVATE ${KOMA_WARNINGS})
target_link_libraries(koma_page_lib PUBLIC koma_server_lib koma_client_lib
  PRIVATE civetweb::civetweb nlohmann_json::nlohmann_json absl::strings)
target_link_libraries(koma_server PRIVATE koma_page_lib)
