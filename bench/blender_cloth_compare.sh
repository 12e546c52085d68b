#!/usr/bin/env bash
# Blender's cloth solver against foldcast's fold model: the default cotton and every shipped
# look x 3 insets, each at two grid spacings (at most 1.04 cm: 50x69; at most 0.7 cm: 73x101),
# each run until the cloth is at rest (bench/blender_cloth_compare.py).
#   bench/blender_cloth_compare.sh [CSV] [SPACINGS]
# SPACINGS: "coarse", "fine" or "coarse fine" (default): the coarse grid for every case first,
# so that a partial sweep already covers every case once.  Runs Blender (Debian `blender`,
# headless) once per case and grid that CSV does not hold yet and appends its row, so an
# interrupted sweep resumes, then prints the comparison (bench/blender_cloth_table.py CSV,
# seconds; it can be re-run alone without Blender).  Heavy (minutes per case on the fine
# grid): not part of the build, the tests or CI.  Run it in the background with a log.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
csv="${1:-$root/bench/blender_cloth.csv}"
spacings="${2:-coarse fine}"
foldcast="${FOLDCAST:-$root/build/foldcast}"
width=0.5 height=0.7
header="name,width_m,height_m,inset_m,thickness_mm,young_mpa,gsm,poisson,nu,nv,sign_changes,crest_heights_m,settle_speed_m_s,blender_s,centre_fibre,top_edge_m,centre_fibre_m,spacing_m,at_rest,settle_frames,fold_depth_m,hem_width_m,hem_centre_m,hem_corners_m"
[ -s "$csv" ] || echo "$header" > "$csv"
run_case() {  # NAME INSET THICKNESS_MM YOUNG_MPA GSM POISSON NU NV
  if awk -F, -v n="$1" -v d="$2" -v u="$7" -v v="$8" \
       '$1 == n && $4 == d && $9 == u && $10 == v { found = 1 } END { exit !found }' "$csv"; then
    return
  fi
  echo "$(date -u +%H:%M:%S) $1 inset $2 grid ${7}x$8" >&2
  row=$(blender -b --factory-startup -P "$here/blender_cloth_compare.py" -- \
          "$1" "$width" "$height" "$2" "$3" "$4" "$5" "$6" "$7" "$8" 2>/dev/null |
        sed -n 's/^RESULT,//p')
  [ -n "$row" ] && echo "$row" >> "$csv"
  return 0
}
cases() {  # the default cotton first, then every look x 3 insets: NAME INSET T E GSM NU
  echo "default_cotton 0.1 0.3 5.0 150.0 0.3"
  for look in $("$foldcast" looks --json | python3 -c 'import json,sys; print(" ".join(l["name"] for l in json.load(sys.stdin)["looks"]))'); do
    read -r t e gsm nu_p < <("$foldcast" looks show "$look" --json | python3 -c \
      'import json,sys; m=json.load(sys.stdin)["mechanics"]; print(m["thickness_mm"], m["young_mpa"], m["gsm"], m["poisson"])')
    for inset in 0.05 0.1 0.15; do echo "$look $inset $t $e $gsm $nu_p"; done
  done
}
list=$(cases)
for spacing in $spacings; do
  case "$spacing" in
    coarse) grid="50 69" ;;   # 1.02 x 1.03 cm
    fine) grid="73 101" ;;    # 0.69 x 0.70 cm
    *) echo "blender_cloth_compare.sh: spacing '$spacing': use coarse and/or fine" >&2; exit 2 ;;
  esac
  while read -r name inset t e gsm nu_p; do
    # shellcheck disable=SC2086
    run_case "$name" "$inset" "$t" "$e" "$gsm" "$nu_p" $grid
  done <<< "$list"
done
python3 "$here/blender_cloth_table.py" "$csv" "$foldcast"
