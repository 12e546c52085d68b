#!/usr/bin/env bash
# One visual regression check: renders scene NAME of scenes.txt with FOLDCAST and compares it
# with tests/golden/NAME.png by `foldcast diff` (idiff conventions).  On a pass nothing is
# kept; otherwise ARTIFACTS/NAME/ keeps new.png (the render), heat.png (FLIP heat-map),
# abs.png (|A-B| heat-map), golden.png (a copy) and diff.json, and their paths are printed.
#   usage: check.sh FOLDCAST NAME ARTIFACTS
# Exit 0 pass (or warning), 1 failure or error.
set -uo pipefail
if [ $# -ne 3 ]; then echo "usage: $0 FOLDCAST NAME ARTIFACTS" >&2; exit 1; fi
FOLDCAST=$1 NAME=$2 ARTIFACTS=$3
source "$(dirname "${BASH_SOURCE[0]}")/scene_line.sh"
source "$REGRESSION_DIR/thresholds.sh"
scene_line "$NAME" || exit 1
GOLDEN="$REPO_ROOT/tests/golden/$NAME.png"
OUT="$ARTIFACTS/$NAME"
rm -rf "$OUT" && mkdir -p "$OUT" || exit 1

# Two threads, while bless.sh uses every core: the image must not depend on the count.
if ! "$FOLDCAST" render "$SCENE" -o "$OUT/new.png" --width "$WIDTH" --height "$HEIGHT" --spp "$SPP" \
        --seed "$SEED" --threads 2 --quiet; then
    echo "regression $NAME: foldcast render failed (scene $SCENE)"
    exit 1
fi
"$FOLDCAST" diff "$GOLDEN" "$OUT/new.png" -o "$OUT/heat.png" --json "${DIFF_THRESHOLDS[@]}" >"$OUT/diff.json"
status=$?
echo "regression $NAME: $(cat "$OUT/diff.json")"
case $status in
    0) rm -rf "$OUT"; echo "regression $NAME: PASS"; exit 0 ;;
    1) echo "regression $NAME: WARNING (within the failure thresholds; kept for a look):" ;;
    *) echo "regression $NAME: FAILURE (foldcast diff exit $status) against $GOLDEN" ;;
esac
cp -f "$GOLDEN" "$OUT/golden.png" 2>/dev/null
"$FOLDCAST" diff "$GOLDEN" "$OUT/new.png" -o "$OUT/abs.png" --heatmap abs >/dev/null 2>&1
for f in new.png heat.png abs.png golden.png diff.json; do
    [ -e "$OUT/$f" ] && echo "  artifact: $OUT/$f"
done
if [ "$status" -ge 2 ]; then
    echo "  If the change is intended, re-bless: tests/regression/bless.sh (see docs/compare.md)."
    exit 1
fi
exit 0
