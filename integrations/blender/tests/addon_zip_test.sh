#!/usr/bin/env bash
# Runs addon_zip_test.py in headless Blender with its user scripts and config folders in a
# scratch folder (the installer writes there, never in the user's ~/.config/blender), removed
# on exit. Usage: addon_zip_test.sh BLENDER KOMA_SERVER ADDON_ZIP VERSION
set -euo pipefail
blender=$1 server=$2 zip=$3 version=$4
here=$(cd "$(dirname "$0")" && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
[ -f "$zip" ] || { echo "FAIL: no $zip (build the koma_blender_zip target)" >&2; exit 1; }
mkdir -p "$scratch/scripts" "$scratch/config"
env -u KOMA_PYTHONPATH BLENDER_USER_SCRIPTS="$scratch/scripts" \
  BLENDER_USER_CONFIG="$scratch/config" PYTHONDONTWRITEBYTECODE=1 \
  "$blender" -b --factory-startup --python-exit-code 1 --python "$here/addon_zip_test.py" -- \
  "$server" "$zip" "$version"
