#!/usr/bin/env bash
# foldcast's .glb in Blender's glTF importer (Debian `blender`, headless), by hand, not CI:
# a static denim garment against its OBJ and a 24-frame animation (--uncompressed: Blender's
# importer has no EXT_meshopt_compression) against its PC2; prints the vertex error, the
# shape keys and the material as Blender reads it (bench/gltf_blender.py).
#   bench/gltf_blender.sh [BUILD]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${1:-$(dirname "$here")/build}"
command -v blender >/dev/null || { echo "no blender on PATH (apt-get install blender)"; exit 0; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$build/foldcast" drape --grid 32x40 --look denim -q -o "$tmp/static.glb" >/dev/null
"$build/foldcast" drape --grid 32x40 --look denim -q -o "$tmp/static.obj" >/dev/null
anim=(drape --grid 32x40 --frames 24 --sway-m 0.02 --look velvet -q)
"$build/foldcast" "${anim[@]}" --uncompressed -o "$tmp/anim.glb" >/dev/null
"$build/foldcast" "${anim[@]}" -o "$tmp/anim.pc2" >/dev/null
"$build/foldcast" "${anim[@]}" --max-error-m 0 -o "$tmp/quantized.glb" >/dev/null
blender --version | head -1
# The compressed file last: Blender 3.4's importer refuses EXT_meshopt_compression (it says so).
for case in "static.glb static.obj" "anim.glb anim.pc2" "quantized.glb anim.pc2"; do
  set -- $case
  echo "== $1 against $2"
  blender -b --factory-startup -P "$here/gltf_blender.py" -- "$tmp/$1" "$tmp/$2" 2>&1 | sed -n 's/^RESULT //p;/Error\|error:/p' | head -30
done
