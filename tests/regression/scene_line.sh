# Sourced by check.sh and bless.sh.  scene_line NAME: sets SCENE WIDTH HEIGHT SPP SEED from
# scenes.txt, or fails.  scene_names: every name in scenes.txt.
REGRESSION_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO_ROOT=$(cd "$REGRESSION_DIR/../.." && pwd)
scene_names() { grep -v '^\s*\(#\|$\)' "$REGRESSION_DIR/scenes.txt" | awk '{print $1}'; }
scene_line() {
    local line
    line=$(grep -v '^\s*#' "$REGRESSION_DIR/scenes.txt" | awk -v n="$1" '$1 == n')
    if [ -z "$line" ]; then echo "regression: no scene named '$1' in $REGRESSION_DIR/scenes.txt" >&2; return 1; fi
    read -r _ SCENE WIDTH HEIGHT SPP SEED <<<"$line"
    SCENE="$REPO_ROOT/$SCENE"
}
