#!/usr/bin/env bash
# Times a 36-frame 1280x720 EGL preview turntable of the default scene (issue target: under
# 10 s on 2 cores with Mesa llvmpipe) next to one path-traced preview-size frame.
#   bench/bench_preview_turntable.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
fc=${1:-build}/foldcast
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
start=$(date +%s.%N)
$fc turntable gallery/default.toml --preview -o "$out/frames/" --frames 36 --width 1280 --height 720 --quiet
end=$(date +%s.%N)
awk -v a="$start" -v b="$end" 'BEGIN { printf "preview turntable, 36 frames 1280x720 (4x MSAA): %.2f s wall\n", b - a }'
$fc preview gallery/default.toml -o "$out/still.png" --json
