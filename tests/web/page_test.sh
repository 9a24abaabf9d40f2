#!/usr/bin/env bash
# koma's page (docs/page.md) end to end: the real koma_server with its HTTP port on loopback,
# the page driven in Debian's headless chromium (page_browser.py), its downloads against the
# real koma CLI.
#   page_test.sh KOMA_SERVER KOMA SAMPLES_DIR TESTDATA_DIR PYTHON
# KOMA_PAGE_SHOTS=DIR keeps the screenshots (page_1280.png, page_390.png).
set -euo pipefail
server_bin=$1 koma=$2 samples=$3 testdata=$4 python=$5
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../e2e/lib.sh
source "$here/../e2e/lib.sh"

start_server "$server_bin" --http_port=0 --http_port_file="$work/http.port"
wait_until 10 test -s "$work/http.port" || fail "no HTTP port file within 10 s"
http=$(cat "$work/http.port")
"$python" "$here/page_browser.py" "http://127.0.0.1:$http/" "$koma" "$target" "$samples" \
  "$testdata" "$work" || fail "the page in chromium"
stop_server
echo "ok: the page"
