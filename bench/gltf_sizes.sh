#!/usr/bin/env bash
# The same drape animation as .fca (codec default profile), PC2 (+ its OBJ topology) and .glb
# (morph targets: compressed at the finest quantization and at the .fca's own error bound, and
# --uncompressed), with no look (geometry only) and in denim (the baked textures added); prints
# bytes, bytes per vertex per frame and the largest position error.
# Usage: bench/gltf_sizes.sh [BUILD] [GRID] [FRAMES]   (defaults build 64x64 120)
set -euo pipefail
build="${1:-build}" grid="${2:-64x64}" frames="${3:-120}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
anim=(drape --grid "$grid" --frames "$frames" --sway-m 0.02 -q)
"$build/foldcast" "${anim[@]}" -o "$tmp/a.pc2" >/dev/null
# The .fca drape -o x.fca writes (the codec's default profile and bound, 2e-4 x the diagonal),
# through encode for its --json error report.
fca_error=$("$build/foldcast" encode "$tmp/a.pc2" --fps 30 -q --json -o "$tmp/a.fca" | python3 -c 'import json,sys; print(json.load(sys.stdin)["max_error_m"])')
glb_error=$("$build/foldcast" "${anim[@]}" --json -o "$tmp/a.glb" | python3 -c 'import json,sys; print(json.load(sys.stdin)["glb"]["max_position_error_m"])')
coarse_error=$("$build/foldcast" "${anim[@]}" --max-error-m "$fca_error" --json -o "$tmp/coarse.glb" | python3 -c 'import json,sys; print(json.load(sys.stdin)["glb"]["max_position_error_m"])')
"$build/foldcast" "${anim[@]}" --uncompressed -o "$tmp/float.glb" >/dev/null
"$build/foldcast" "${anim[@]}" --look denim -o "$tmp/denim.glb" >/dev/null
vertices=$(( ${grid%x*} * ${grid#*x} ))
# name, bytes, max error, file(s) for the gzip -9 size (what HTTP compression sends)
row() {
  printf '%-52s %10d bytes %6.2f B/vertex/frame  gzip -9 %10d  max error %.3g m\n' "$1" "$2" \
    "$(echo "$2 / ($vertices * $frames)" | bc -l)" "$(cat "${@:4}" | gzip -9 | wc -c)" "$3"
}
echo "drape animation: grid $grid ($vertices vertices), $frames frames"
row ".fca (codec default profile and bound)" "$(stat -c %s "$tmp/a.fca")" "$fca_error" "$tmp/a.fca"
row "PC2 + OBJ topology" "$(( $(stat -c %s "$tmp/a.pc2") + $(stat -c %s "$tmp/a.obj") ))" 0 "$tmp/a.pc2" "$tmp/a.obj"
row ".glb quantized + meshopt (no look)" "$(stat -c %s "$tmp/a.glb")" "$glb_error" "$tmp/a.glb"
row ".glb quantized + meshopt, --max-error-m the .fca's" "$(stat -c %s "$tmp/coarse.glb")" "$coarse_error" "$tmp/coarse.glb"
row ".glb float, --uncompressed (no look)" "$(stat -c %s "$tmp/float.glb")" 0 "$tmp/float.glb"
row ".glb quantized + meshopt, denim (textures)" "$(stat -c %s "$tmp/denim.glb")" "$glb_error" "$tmp/denim.glb"
