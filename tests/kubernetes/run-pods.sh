#!/usr/bin/env bash
# The Indexed Job's pods without Kubernetes: its container's command (from the manifest, as
# Kubernetes would run it: foldcast on PATH, in the working directory that holds catalogue.toml)
# once for each JOB_COMPLETION_INDEX 0..completions-1, on a small catalogue; the union of the
# pods' outputs must equal one unsharded run byte for byte, and a pod run again must skip.
#   tests/kubernetes/run-pods.sh BUILD/foldcast [MANIFEST.yaml]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
foldcast=$(realpath "${1:?usage: $0 BUILD/foldcast [MANIFEST.yaml]}")
manifest=$(realpath "${2:-$here/../../docs/scale-out/foldcast-indexed-job.yaml}")
if ! command -v node >/dev/null || [ ! -d "$here/node_modules/yaml" ] || ! command -v jq >/dev/null; then
  why="node, jq or $here/node_modules (npm ci --prefix tests/kubernetes) missing"
  if [ "${CI:-}" = true ]; then echo "$0: $why" >&2; exit 1; fi
  echo "$0: SKIPPED: $why (with CI=true this fails)" >&2
  exit 77
fi
mapfile -t argv < <(node "$here/validate-manifest.mjs" --print-command "$manifest")
completions=$(grep -oP '^\s*completions:\s*\K[0-9]+' "$manifest")
[ "${#argv[@]}" -gt 0 ] && [ "$completions" -gt 1 ] || { echo "FAIL: no command or completions in $manifest" >&2; exit 1; }

work=$(mktemp -d /tmp/foldcast-pods.XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/bin" "$work/volume"
ln -s "$foldcast" "$work/bin/foldcast"  # the image's /usr/local/bin/foldcast
cd "$work/volume"
printf '[garment]\npath = "%s"\nscale = 0.1\n' "$(realpath "$here/../data/animations/basicCloth.obj")" >tiny.toml
catalogue() {  # 9 images, tiny: 3 looks x 3 views
  cat <<EOT
output_dir = "$1"
width = 40
height = 30
spp = 2
looks = ["denim", "chiffon", "linen"]
[[garments]]
name = "cloth"
scene = "tiny.toml"
[[views]]
name = "front"
[[views]]
name = "side"
azimuth_deg = 60
[[views]]
name = "back"
azimuth_deg = 180
EOT
}
catalogue out >catalogue.toml
catalogue ref >ref.toml
"$foldcast" batch ref.toml --quiet

# A pod's environment: little more than PATH and the index Kubernetes sets.
pod() { env -i PATH="$work/bin:/usr/bin:/bin" HOME="$work" JOB_COMPLETION_INDEX="$1" "${argv[@]}" >"pod-$1.log" 2>&1; }
for ((i = 0; i < completions; i++)); do
  pod "$i" || { cat "pod-$i.log" >&2; echo "FAIL: pod $i exited non-zero" >&2; exit 1; }
done
diff -r --exclude='outputs*.json' ref out || { echo "FAIL: the pods' images differ from the unsharded run" >&2; exit 1; }
lists=()
for ((i = 0; i < completions; i++)); do lists+=("out/outputs-$i-of-$completions.json"); done
cmp <(jq -s 'add | sort_by(.index)' "${lists[@]}") ref/outputs.json ||
  { echo "FAIL: the pods' lists differ from outputs.json" >&2; exit 1; }
pod 3
grep -q "^shard 3/$completions: job 1 of .* already finished" pod-3.log ||
  { cat pod-3.log >&2; echo "FAIL: a retried pod did not skip" >&2; exit 1; }
echo "$completions pods of $manifest: their outputs equal the unsharded run; a retried pod skips"
