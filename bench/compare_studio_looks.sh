#!/usr/bin/env bash
# The photo pipeline on studio pictures of known drapes: for each look, foldcast renders the
# scene of tests/compare/scenes/studio_sag.toml (0.6 x 0.55 m panel on clips against the grey
# cyclorama) at the given inset, then `foldcast overlay --fit` reads it back with the
# supports where the camera sees them.  Prints the model's n beside the measured and fitted
# n and the score (docs/compare.md, "Studio picture tests").
#   bench/compare_studio_looks.sh [build-dir] [inset_m] [width] [height]
set -euo pipefail
cd "$(dirname "$0")/.."
fc=${1:-build}/foldcast
inset=${2:-0.08}
width=${3:-640}
height=${4:-480}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The scene's camera: 5 m away, 8 degrees vertical field of view, aimed 0.25 m below the
# supports (x = +/- span / 2, y = 0); pixels per metre at the picture's height.
span=$(awk -v i="$inset" 'BEGIN { print 0.6 - 2 * i }')
supports=$(awk -v s="$span" -v w="$width" -v h="$height" 'BEGIN {
  f = h / (2 * 5.0 * sin(4 * atan2(1, 1) / 45) / cos(4 * atan2(1, 1) / 45));
  printf "%.1f,%.1f,%.1f,%.1f", w / 2 - f * s / 2, h / 2 - f * 0.25, w / 2 + f * s / 2, h / 2 - f * 0.25 }')
printf "%-18s %7s %8s %8s %6s %6s\n" look model measured fitted lines F1
for look in cotton_poplin cotton_jersey linen denim canvas chiffon satin silk_charmeuse wool_flannel velvet; do
  sed -e "s/^look = .*/look = \"$look\"/" -e "s/^inset_m = .*/inset_m = $inset/" \
      -e "s/^width = .*/width = $width/" -e "s/^height = .*/height = $height/" \
      tests/compare/scenes/studio_sag.toml > "$out/scene.toml"
  $fc render "$out/scene.toml" -o "$out/photo.png" --quiet
  model=$($fc drape --look "$look" --width-m 0.6 --height-m 0.55 --inset-m "$inset" --no-relax --json |
          python3 -c 'import json, sys; print(json.load(sys.stdin)["folds"])')
  $fc overlay "$out/photo.png" -o "$out/overlay.png" --supports "$supports" --look "$look" --fit --json |
    python3 -c 'import json, sys
d = json.load(sys.stdin)
print("%-18s %7s %8d %8d %6d %6.2f" % (sys.argv[1], sys.argv[2], d["measured"]["folds"], d["predicted"]["folds"],
      d["detected_lines"], d["score"]["f1"]))' "$look" "$model"
done
