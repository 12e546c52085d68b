#!/usr/bin/env bash
# Blender's cloth solver against foldcast's fold model: every shipped look x 3 insets.
#   bench/blender_cloth_compare.sh [CSV] [NU NV]
# Runs Blender (Debian `blender`, headless) once per case that CSV does not hold yet and
# appends its row, so an interrupted sweep resumes, then prints the comparison table
# (bench/blender_cloth_table.py CSV, seconds; it can be re-run alone without Blender).  The
# default cotton (foldcast drape's defaults) at inset 0.1 m comes first.  Heavy: not part of
# the build, the tests or CI.  Run it in the background with a log.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
csv="${1:-$root/bench/blender_cloth.csv}"
nu="${2:-25}"
nv="${3:-35}"
foldcast="${FOLDCAST:-$root/build/foldcast}"
width=0.5 height=0.7
if [ ! -s "$csv" ]; then
  echo "name,width_m,height_m,inset_m,thickness_mm,young_mpa,gsm,poisson,nu,nv,sign_changes,crest_heights_m,settle_speed_m_s,blender_s,centre_fibre,top_edge_m,centre_fibre_m" > "$csv"
fi
run_case() {  # NAME INSET THICKNESS_MM YOUNG_MPA GSM POISSON
  if grep -q "^$1,$width,$height,$2," "$csv"; then return; fi
  echo "$(date -u +%H:%M:%S) $1 inset $2" >&2
  row=$(blender -b --factory-startup -P "$here/blender_cloth_compare.py" -- \
          "$1" "$width" "$height" "$2" "$3" "$4" "$5" "$6" "$nu" "$nv" 2>/dev/null |
        sed -n 's/^RESULT,//p')
  [ -n "$row" ] && echo "$row" >> "$csv"
  return 0
}
run_case default_cotton 0.1 0.3 5.0 150.0 0.3
for look in $("$foldcast" looks --json | python3 -c 'import json,sys; print(" ".join(l["name"] for l in json.load(sys.stdin)["looks"]))'); do
  read -r t e gsm nu_p < <("$foldcast" looks show "$look" --json | python3 -c \
    'import json,sys; m=json.load(sys.stdin)["mechanics"]; print(m["thickness_mm"], m["young_mpa"], m["gsm"], m["poisson"])')
  for inset in 0.05 0.1 0.15; do run_case "$look" "$inset" "$t" "$e" "$gsm" "$nu_p"; done
done
python3 "$here/blender_cloth_table.py" "$csv" "$foldcast"
