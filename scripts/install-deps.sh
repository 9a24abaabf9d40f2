#!/usr/bin/env bash
# Installs koma's build and test dependencies from Debian 12's packages. Idempotent: it only
# calls apt-get when a package is missing, so a second run costs a dpkg query.
set -euo pipefail

# What building koma_server and koma needs (ninja-build, lld and ccache: faster builds, links
# and rebuilds, scripts/build.sh; liblo-dev and libasound2-dev: `koma live` sends VMC's OSC
# through liblo and captures the microphone through ALSA; libcivetweb-dev: its WebSocket client
# talks to VTube Studio, named here although prometheus-cpp-dev brings it too).
packages=(
  cmake g++ make ninja-build lld ccache pkg-config
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libabsl-dev libspdlog-dev libfmt-dev
  nlohmann-json3-dev libcli11-dev
  libtinygltf-dev
  prometheus-cpp-dev
  libsndfile1-dev
  zlib1g-dev
  liblo-dev libasound2-dev libcivetweb-dev
)
# What the tests and benchmarks add (python3-grpcio: the interop test's second client;
# buildah, podman, runc, debootstrap: deploy/test-image.sh builds and runs the image;
# nginx: the scale-out test puts it in front of two servers on loopback; python3-pytest: the
# Python package's tests; blender: the add-on's headless test, whose bundled Python imports
# Debian's python3-grpcio; chromium, python3-html5lib, python3-pil, fonts-dejavu-core: the
# --report tests open the reports in headless chromium, validate them as HTML5 and check their
# screenshots; clang, its sanitizer and libFuzzer runtimes and llvm-symbolizer:
# scripts/test-sanitizers.sh and scripts/fuzz.sh).
# `install-deps.sh --build-only` skips them (the Dockerfile's build stage).
if [ "${1:-}" != "--build-only" ]; then
  packages+=(libgtest-dev libgmock-dev libbenchmark-dev python3 python3-grpcio python3-protobuf
             python3-yaml python3-pytest openssl blender
             buildah podman runc debootstrap nginx
             chromium python3-html5lib python3-pil fonts-dejavu-core
             clang libclang-rt-14-dev llvm)
  # python3-jsonschema: the client tests validate `koma ... --json` against
  # docs/summary.schema.json.
  packages+=(python3-jsonschema)
  # jq, bsdextrautils (column): docs/usage.md's examples pipe into them, and the docs test
  # runs every documented command.
  packages+=(jq bsdextrautils)
  # espeak-ng, sox, libsox-fmt-all, sndfile-programs: the LipBlink audio tests speak known
  # sentences, join them with known silences and noise, and write them as WAV, FLAC, Ogg
  # Vorbis/Opus and MP3 (tests/testing/voice_recordings.py); nothing is downloaded.
  packages+=(espeak-ng sox libsox-fmt-all sndfile-programs)
  # python3-numpy: Blender's glTF exporter and importer (io_scene_gltf2) import numpy; the glTF
  # tests export the test BVHs through it and read koma's .glb back.
  packages+=(python3-numpy)
  # python3-build, python3-venv: the wheel test builds the Python package's wheel offline and
  # installs it into a fresh venv; slurm-wlm, munge: the render-farm test runs a Slurm job
  # array on a controller and a node daemon it starts on localhost; nodejs: the sharding test
  # compiles the Flamenco job type (deploy/farm/koma-batch.js) as Flamenco's manager would, and
  # three.js, the second glTF consumer of tests/e2e/gltf, runs under it (npm where the nodejs
  # package does not bring it: npm ci installs three.js from the committed lock).
  packages+=(python3-build python3-venv slurm-wlm munge nodejs)
  if ! command -v npm >/dev/null 2>&1; then packages+=(npm); fi
  # catatonit: `podman kube play` (deploy/test-image.sh) builds the pod's pause image from it.
  packages+=(catatonit)
  # curl: the HTTP port's tests call the Connect JSON API as a user would
  # (tests/e2e/http_api_e2e_test.sh).
  packages+=(curl)
  # libcurl4-openssl-dev: koma_http_load (bench/http_load.cc) drives the HTTP port through it.
  packages+=(libcurl4-openssl-dev)
  # libassimp-dev: Debian's assimp is the third reader of the FBX files koma writes
  # (blender.fbx_retimed builds tests/e2e/fbx/assimp_poses against it, pivots off, beside
  # Blender's importer and three.js's FBXLoader).
  packages+=(libassimp-dev)
  # liblo-tools (oscdump), python3-liblo: the live tests receive koma live's VMC bundles with a
  # real OSC receiver; python3-websockets: the stand-in for VTube Studio's API server and
  # `python3 -m koma live --vts` (tests/python/test_live_vts.py);
  # alsa-utils: aplay/arecord and the ALSA configuration the capture test's null device uses.
  packages+=(liblo-tools python3-liblo python3-websockets alsa-utils)
fi

# The tests' npm packages, exactly as tests/e2e/gltf/package-lock.json pins them (into
# tests/e2e/gltf/node_modules, ignored by git); again only when the lock changed.
install_npm_test_packages() {
  local dir
  dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/e2e/gltf"
  if [ -f "$dir/node_modules/.package-lock.json" ] &&
     cmp -s <(sed -n '/"node_modules\//,$p' "$dir/package-lock.json") \
            <(sed -n '/"node_modules\//,$p' "$dir/node_modules/.package-lock.json"); then
    return 0
  fi
  echo "install-deps: npm ci in tests/e2e/gltf (three.js for the glTF tests)"
  (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
}

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  if [ "${1:-}" != "--build-only" ]; then install_npm_test_packages; fi
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive

# Packages such as nginx start a system service on 0.0.0.0 when installed. koma's tests start
# their own servers on loopback only, so service starts are refused for the length of the
# install (policy-rc.d exit 101 = "action forbidden", see invoke-rc.d(8)).
policy=/usr/sbin/policy-rc.d
made_policy=0
if [ ! -e "$policy" ]; then
  printf '#!/bin/sh\nexit 101\n' | "${sudo_cmd[@]}" tee "$policy" >/dev/null
  "${sudo_cmd[@]}" chmod 755 "$policy"
  made_policy=1
fi
remove_policy() {
  if [ "$made_policy" = 1 ]; then "${sudo_cmd[@]}" rm -f "$policy"; fi
  return 0
}
trap remove_policy EXIT

# Two builds installing at once (two clones, or a build beside the test run) would race for
# dpkg's lock: the second waits for the first instead of failing.
"${sudo_cmd[@]}" flock /tmp/koma-install-deps.lock sh -c \
  'apt-get update -qq && apt-get install -y -qq --no-install-recommends "$@"' sh "${missing[@]}"
if [ "${1:-}" != "--build-only" ]; then install_npm_test_packages; fi
