#!/bin/sh
# SPDX-License-Identifier: MIT
# examples/run_scene.cpp (a scene run from C++ with tumble::Run, docs/cpp.md) against tumble run on
# scenes/pour.toml, a scene whose bodies all come from a [[pour]]: the same recording and time
# series, byte for byte, and every poured body entered.
#   run_scene_test.sh RUN_SCENE TUMBLE SOURCE_DIR
set -eu
run_scene=$1 tumble=$2 scene=$3/scenes/pour.toml
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$run_scene" "$scene" --steps 12000 --record "$dir/cpp.bin" --thermo "$dir/cpp.csv" >"$dir/out.txt"
"$tumble" run "$scene" --steps 12000 -q --record "$dir/cli.bin" --thermo "$dir/cli.csv"
cmp "$dir/cpp.bin" "$dir/cli.bin"
cmp "$dir/cpp.csv" "$dir/cli.csv"
if ! tail -n 1 "$dir/out.txt" | grep -q "step 12000 .* 300 bodies"; then
  echo "run_scene: the pour's 300 bodies have not all entered by step 12000:" >&2
  cat "$dir/out.txt" >&2
  exit 1
fi
echo "run_scene = tumble run on scenes/pour.toml (recording and time series), 300 bodies poured"
