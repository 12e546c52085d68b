#!/usr/bin/env bash
# validate-manifest.mjs --self-test on the shipped Indexed Job, for CTest.  Without node or
# this folder's node_modules (npm ci, .ci/install-deps): a failure in CI (CI=true), elsewhere
# a skip that says why (exit 77).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
missing=""
command -v node >/dev/null || missing="node (Debian's nodejs)"
[ -d "$here/node_modules/kubernetes-models" ] ||
  missing="${missing:+$missing and }$here/node_modules (npm ci --prefix tests/kubernetes)"
if [ -n "$missing" ]; then
  if [ "${CI:-}" = true ]; then echo "$0: missing $missing" >&2; exit 1; fi
  echo "$0: SKIPPED: missing $missing (with CI=true this fails)" >&2
  exit 77
fi
exec node "$here/validate-manifest.mjs" --self-test "${1:-$here/../../docs/scale-out/foldcast-indexed-job.yaml}"
