#!/usr/bin/env bash
# Renders every gallery scene into gallery/out/, with a contact sheet (contact-sheet.png)
# and an index.html.  Run from anywhere after building (build/foldcast must exist).
#   gallery/make-gallery.sh            # catalogue quality, a few minutes on 2 cores
#   gallery/make-gallery.sh --quick    # small and noisy, about a minute
set -euo pipefail
cd "$(dirname "$0")/.."
fc=build/foldcast
out=gallery/out
[ -x "$fc" ] || { echo "make-gallery: build first (cmake -S . -B build && cmake --build build)" >&2; exit 2; }
quick=0
[ "${1:-}" = "--quick" ] && quick=1
# Catalogue quality: adaptive sampling and the denoiser (docs/render.md); quick: few plain samples.
if [ $quick = 1 ]; then
  still=(--spp 4); turn=(--spp 2); swatch=(--spp 4)
else
  still=(--spp 64 --denoise --noise-threshold 0.01); turn=(--spp 16 --denoise --noise-threshold 0.02)
  swatch=(--spp 32 --denoise --noise-threshold 0.02)
fi
mkdir -p "$out"
step() { echo "== $*" >&2; }

step "default scene"
$fc render gallery/default.toml -o $out/default.png --width 960 --height 540 "${still[@]}" --quiet
step "EGL preview of the default scene"
$fc preview gallery/default.toml -o $out/preview.png --width 960 --height 540 --quiet || echo "(no EGL here: preview skipped)" >&2
step "tall vs short, soft vs stiff"
for s in tall short soft stiff; do
  $fc render gallery/$s.toml -o $out/$s.png --width 480 --height 600 "${still[@]}" --quiet
done
step "a curtain on 5 hooks (4 bays)"
$fc render gallery/curtain.toml -o $out/curtain.png --width 480 --height 600 "${still[@]}" --quiet
step "every look as a swatch sheet"
$fc looks --swatches $out/swatches.png "${swatch[@]}" --quiet
step "a satin drape animation through the .fca codec"
$fc drape --look satin --width-m 0.6 --height-m 0.8 --inset-m 0.12 --grid 64x96 --frames 48 -o $out/anim.fca --quiet
$fc render gallery/animated.toml -o $out/animated.png --width 480 --height 480 "${still[@]}" --quiet
step "turntable of the animation (path traced)"
$fc turntable gallery/animated.toml -o $out/turntable.mp4 --width 320 --height 320 "${turn[@]}" --quiet
step "fold lines over a real photograph"
$fc overlay tests/data/photos/two_point_shirt_s5_half.jpg -o $out/overlay.png \
    --supports 197.5,50,357.5,48.5 --scale-px-per-m 400 --look cotton_jersey --fit > $out/overlay.json

step "contact sheet and index.html"
tiles=(default preview tall short soft stiff curtain animated swatches overlay)
inputs=(); filters=""; layout=""
i=0
for t in "${tiles[@]}"; do
  [ -f $out/$t.png ] || continue
  inputs+=(-i $out/$t.png)
  filters+="[$i]scale=400:300:force_original_aspect_ratio=decrease,pad=400:300:(ow-iw)/2:(oh-ih)/2:color=0xeeeeee[t$i];"
  layout+="$(( (i % 3) * 400 ))_$(( (i / 3) * 300 ))|"
  i=$((i + 1))
done
stack=""; for k in $(seq 0 $((i - 1))); do stack+="[t$k]"; done
ffmpeg -loglevel error -y "${inputs[@]}" -filter_complex "${filters}${stack}xstack=inputs=$i:layout=${layout%|}:fill=0xeeeeee" \
    -frames:v 1 $out/contact-sheet.png

caption() {
  case $1 in
    default) echo "The default scene: linen on a rod (gallery/default.toml), path traced";;
    preview) echo "The same scene as an EGL preview (foldcast preview)";;
    tall) echo "Tall cotton poplin: many folds";;
    short) echo "Short cotton poplin: few folds";;
    soft) echo "Soft: chiffon, many fine folds";;
    stiff) echo "Stiff: canvas, two broad folds";;
    curtain) echo "A linen curtain on 5 hooks: 4 bays sharing their inner hooks";;
    animated) echo "Satin drape animation decoded from .fca, last frame";;
    swatches) echo "Every look draped the same way";;
    overlay) echo "Predicted fold lines over a real photo (black: crests, dashed white: valleys)";;
  esac
}
{
  echo "<!doctype html><html><head><meta charset=utf-8><title>foldcast gallery</title>"
  echo "<style>body{font-family:sans-serif;margin:2em}figure{display:inline-block;margin:1em;vertical-align:top}img,video{max-width:460px}</style></head><body>"
  echo "<h1>foldcast gallery</h1><p>Made by <code>gallery/make-gallery.sh</code>. <a href=contact-sheet.png>Contact sheet</a>.</p>"
  for t in "${tiles[@]}"; do
    [ -f $out/$t.png ] && echo "<figure><img src=$t.png><figcaption>$(caption $t)</figcaption></figure>"
  done
  echo "<figure><video src=turntable.mp4 controls loop></video><figcaption>Turntable of the satin animation (mp4v; frames in turntable_frames/)</figcaption></figure>"
  echo "</body></html>"
} > $out/index.html
echo "gallery written to $out/index.html" >&2
