#!/usr/bin/env bash
# docs/scale-out/foldcast-array.sbatch on a real Slurm, submitted as a user would:
#   tests/slurm/slurm-cluster.sh tests/slurm/array-recipe-test.sh BUILD/foldcast
# 1. sbatch --array=0-3 --wait renders a small catalogue; its images, their .sha256 files and
#    the four outputs-I-of-4.json lists equal one unsharded `foldcast batch` run byte for byte.
# 2. A second catalogue: task 1 is cancelled (scancel) while it renders its second image; the
#    array is resubmitted as the docs say; finished shards skip everything, task 1 skips its
#    first image and renders its second; the result again equals the unsharded run, with no
#    temporaries.
# 3. Resubmitting with another N is refused (exit 2) with a message that names both splits.
set -euo pipefail
foldcast=$(realpath "${1:?usage: $0 BUILD/foldcast}")
recipe=$(realpath "$(dirname "$0")/../../docs/scale-out/foldcast-array.sbatch")
data=$(realpath "$(dirname "$0")/../data")
: "${SLURM_CONF:?run under tests/slurm/slurm-cluster.sh}"

work=$(mktemp -d /tmp/foldcast-slurm-test.XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() {
  echo "FAIL: $*" >&2
  for log in "$work"/*.log; do [ -f "$log" ] && { echo "--- $log"; cat "$log"; }; done >&2
  exit 1
}
step() { echo "== $* ($SECONDS s)"; }

# A small catalogue: 8 images (2 garments x 2 looks x 2 views), 2 per shard, each about 1.5 s
# to render on the two cores a task gets, so that a cancel can land in the middle of one.
cat >tiny.toml <<EOF
[garment]
path = "$data/animations/basicCloth.obj"
scale = 0.1
EOF
cat >tiny2.toml <<EOF
[garment]
path = "$data/animations/basicCloth.obj"
scale = 0.12
EOF
catalogue() {
  cat <<EOF
output_dir = "$1"
width = 128
height = 96
spp = 48
looks = ["denim", "chiffon"]
[[garments]]
name = "cloth"
scene = "tiny.toml"
[[garments]]
name = "wide"
scene = "tiny2.toml"
[[views]]
name = "front"
[[views]]
name = "side"
azimuth_deg = 60
EOF
}
catalogue ref >ref.toml
catalogue farm >farm.toml
catalogue retry >retry.toml

# The lists of the four shards, merged in job order, with the `skipped` flags dropped when
# $2 is "noskip" (a resumed run marks what it skipped).
merged() {
  local filter='add | sort_by(.index)'
  [ "${2:-}" = noskip ] && filter="$filter | map(del(.skipped))"
  jq -s "$filter" "$1"/outputs-{0,1,2,3}-of-4.json
}
same_as_reference() {  # DIR [noskip]
  diff -r --exclude='outputs*.json' ref "$1" || fail "$1 differs from the unsharded run (files above)"
  if [ "${2:-}" = noskip ]; then
    cmp <(merged "$1" noskip) <(jq 'map(del(.skipped))' ref/outputs.json) || fail "$1's lists differ from outputs.json"
  else
    cmp <(merged "$1") ref/outputs.json || fail "$1's merged lists differ byte for byte from ref/outputs.json"
  fi
}

step "the unsharded reference: foldcast batch ref.toml"
"$foldcast" batch ref.toml --quiet
[ "$(find ref -name '*.png' | wc -l)" = 8 ] || fail "the reference has not 8 images"

step "1. sbatch --array=0-3 --wait $recipe farm.toml"
export FOLDCAST="$foldcast"
sbatch --array=0-3 --wait --quiet "$recipe" farm.toml || fail "the array failed"
same_as_reference farm
for i in 0 1 2 3; do
  grep -q "^shard $i/4: job 2 of 2 rendered in" foldcast-*_"$i".log || fail "task $i logged no progress line"
done
rm -f foldcast-*.log

step "2. cancel task 1 while it renders its second image"
job=$(sbatch --array=0-3 --parsable "$recipe" retry.toml)
job=${job%%;*}
log1=foldcast-${job}_1.log
for _ in $(seq 1 1200); do
  grep -qs "^shard 1/4: job 1 of 2" "$log1" && break
  sleep 0.1
done
grep -qs "^shard 1/4: job 1 of 2 rendered" "$log1" || fail "task 1 did not render its first image within 120 s"
scancel "${job}_1"
for _ in $(seq 1 600); do
  [ -z "$(squeue --noheader --jobs="$job" --format=%i 2>/dev/null)" ] && break
  sleep 0.2
done
[ -z "$(squeue --noheader --jobs="$job" --format=%i)" ] || fail "the array did not end within 120 s"
grep -q "CANCELLED" "$log1" || fail "task 1 was not cancelled"
if grep -q "^shard 1/4: job 2 of 2" "$log1"; then fail "task 1 finished its second image before the cancel"; fi
[ -f retry/outputs-1-of-4.json ] && fail "the cancelled shard wrote its list"
for i in 0 2 3; do [ -f "retry/outputs-$i-of-4.json" ] || fail "shard $i did not finish"; done
leftovers=$(find retry -name '*.tmp-*')
[ -z "$leftovers" ] || fail "temporaries left by the cancelled task: $leftovers"
"$foldcast" batch retry.toml --status | tee status.txt
grep -q "^shard 1/4: 1 of 2 finished$" status.txt || fail "--status does not show shard 1 half done"
grep -q "^shards with work left: 1 (of 4)$" status.txt || fail "--status does not name shard 1"

step "   resubmit: sbatch --array=0-3 --wait (as docs/scale-out.md says)"
rm -f foldcast-*.log
sbatch --array=0-3 --wait --quiet "$recipe" retry.toml || fail "the resubmitted array failed"
for i in 0 2 3; do
  grep -q "^shard $i/4: job 2 of 2 already finished" foldcast-*_"$i".log || fail "finished shard $i did not skip"
  if grep -q "rendered in" foldcast-*_"$i".log; then fail "finished shard $i rendered again"; fi
done
grep -q "^shard 1/4: job 1 of 2 already finished" foldcast-*_1.log || fail "task 1 rendered its first image again"
grep -q "^shard 1/4: job 2 of 2 rendered in" foldcast-*_1.log || fail "task 1 did not render its second image"
same_as_reference retry noskip
[ "$(jq -s 'add | map(select(.skipped | not)) | length' retry/outputs-{0,1,2,3}-of-4.json)" = 1 ] ||
  fail "the resubmission rendered more than the one missing image"
"$foldcast" batch retry.toml --status | grep -q ": 8 of 8 images finished (100%)" || fail "--status: not complete"

step "3. resubmitting with another N is refused"
rm -f foldcast-*.log
status=0
sbatch --array=0-1 --wait --quiet "$recipe" retry.toml || status=$?
[ "$status" = 2 ] || fail "an array of 2 over a catalogue split into 4: sbatch --wait gave $status, not 2"
grep -q "split into 4 shards, not 2" foldcast-*_0.log || fail "the log does not explain the refused split"
same_as_reference retry noskip
step "passed"
