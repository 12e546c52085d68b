#!/usr/bin/env bash
# Re-renders the visual regression goldens (tests/golden/NAME.png) after an intended change.
#   usage: tests/regression/bless.sh [FOLDCAST] [NAME...]
# FOLDCAST defaults to build/foldcast (a Release build); NAMEs default to every scene in
# tests/regression/scenes.txt.  Review the new PNGs (git diff --stat, an image viewer) and
# commit them with the change that caused them.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/scene_line.sh"
FOLDCAST=${1:-$REPO_ROOT/build/foldcast}
[ $# -gt 0 ] && shift
if [ ! -x "$FOLDCAST" ]; then echo "bless: $FOLDCAST is not an executable foldcast (build it first)" >&2; exit 1; fi
names=("$@")
[ ${#names[@]} -eq 0 ] && mapfile -t names < <(scene_names)
mkdir -p "$REPO_ROOT/tests/golden"
for name in "${names[@]}"; do
    scene_line "$name"
    "$FOLDCAST" render "$SCENE" -o "$REPO_ROOT/tests/golden/$name.png" --width "$WIDTH" --height "$HEIGHT" \
        --spp "$SPP" --seed "$SEED" --quiet
    echo "blessed tests/golden/$name.png ($(stat -c %s "$REPO_ROOT/tests/golden/$name.png") bytes)"
done
