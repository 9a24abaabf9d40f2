#!/usr/bin/env bash
# End to end: the real koma_server on a free loopback port, the real koma client on the
# bundled sample. Usage: skeletal_e2e_test.sh KOMA_SERVER KOMA SAMPLE_BVH
set -euo pipefail
server_bin=$1 client_bin=$2 sample=$3

source "$(dirname "$0")/lib.sh"

KOMA_LOG_FORMAT=json start_server "$server_bin" --worker_threads=2  # format from the environment

# Health.
[ "$("$client_bin" health --server "$target")" = SERVING ] || fail "health is not SERVING"

# The sample, with a timing sheet.
"$client_bin" skeletal "$sample" -o "$work/out.bvh" --timing "$work/timing.csv" \
  --server "$target" --deadline 30 >"$work/summary.txt" || fail "koma skeletal failed"
cat "$work/summary.txt"
grep -q "omitted" "$work/summary.txt" || fail "summary has no omitted line"
in_frames=$(sed -n 's/^Frames:[[:space:]]*//p' "$sample" | tr -d '\r')
out_frames=$(sed -n 's/^Frames:[[:space:]]*//p' "$work/out.bvh")
[ "$in_frames" = "$out_frames" ] || fail "frames $in_frames in, $out_frames out (keep_length)"
rows=$(($(wc -l <"$work/timing.csv") - 1))
[ "$rows" = "$out_frames" ] || fail "timing sheet has $rows rows for $out_frames frames"
head -1 "$work/timing.csv" | grep -q "^output_frame,source_frame,kind" || fail "timing header"
grep -q ",HELD," "$work/timing.csv" || fail "no HELD frame in the timing sheet"
grep -q ",DUPLICATE," "$work/timing.csv" || fail "no DUPLICATE frame in the timing sheet"

# The retimed file is a valid BVH: retime it again.
"$client_bin" skeletal "$work/out.bvh" -o "$work/again.bvh" --server "$target" >/dev/null \
  || fail "the written BVH does not read back"

# Several endpoints, round_robin: a dead one in the list is skipped.
dead=$(free_port)
"$client_bin" skeletal "$sample" -o "$work/rr.bvh" --server "127.0.0.1:$dead,$target" \
  --deadline 20 >/dev/null || fail "a list with a dead endpoint failed"
cmp -s "$work/out.bvh" "$work/rr.bvh" || fail "the round_robin answer differs"
expect_error 2 "server list: must be all IPv4" \
  "$client_bin" health --server "127.0.0.1:1,localhost:2" >/dev/null

# A bad parameter: the server's code and message, exit 1.
expect_error 1 "OUT_OF_RANGE: omissions: 500" \
  "$client_bin" skeletal "$sample" -o "$work/bad.bvh" --omit 500 --server "$target"
[ ! -e "$work/bad.bvh" ] || fail "a failed call wrote an output file"

# Outputs that cannot be written are refused before the call (the server given cannot be
# reached, so an RPC would fail with UNAVAILABLE instead), and nothing is written.
for outputs in "-o $work/missing/out.bvh" "-o $work/early.bvh --timing $work" \
  "-o $work/early.bvh --timing $work/missing/t.csv"; do
  # shellcheck disable=SC2086  # $outputs is a word list
  expect_error 1 "^koma: cannot write $work" \
    "$client_bin" skeletal "$sample" $outputs --server 127.0.0.1:1
  [ ! -e "$work/early.bvh" ] || fail "an unwritable --timing still wrote the BVH"
done

# A usage error: exit 2.
expect_exit 2 "$work/err.txt" "$client_bin" skeletal >/dev/null

# A malformed BVH: exit 1 with the line number.
printf 'HIERARCHY\nROOT Hips\n{\n OFFSET 0 0\n' >"$work/broken.bvh"
expect_error 1 "line" "$client_bin" skeletal "$work/broken.bvh" -o "$work/x.bvh" --server "$target"

# Graceful stop: SIGTERM, exit 0.
stop_server

# Every log line is one JSON object; one per RPC with method and code.
python3 - "$work/server.log" <<'PY' || fail "server log is not JSON lines"
import json, sys
lines = open(sys.argv[1]).read().splitlines()
records = [json.loads(line) for line in lines]
rpcs = [r for r in records if r.get("msg") == "rpc"]
assert len(rpcs) == 4, rpcs  # three retimes and the bad one; usage errors never leave the client
for r in rpcs:
    for key in ("method", "request_id", "peer", "frames", "joints", "bytes_in", "bytes_out",
                "code", "latency_ms"):
        assert key in r, (key, r)
assert any(r["code"] == "OUT_OF_RANGE" for r in rpcs)
assert records[-1]["msg"] == "koma_server stopped"
PY
echo "PASS: skeletal end to end"
