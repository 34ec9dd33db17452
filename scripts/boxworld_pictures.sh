#!/usr/bin/env bash
# Renders six worlds of box-world-complex's broad distribution (floors of
# 4-8 m, 1-6 boxes of all three shapes, random colours; task seeds 0-5) and
# puts them side by side in a 3 x 2 grid (ffmpeg):
#
#   scripts/boxworld_pictures.sh [OUT.png] [CAMERA]
#
# Defaults: docs/media/boxworld_worlds.png, camera perspective (400 x 300
# each); camera top gives 320 x 320 images.
#
# Needs the manyworlds program (MANYWORLDS_BIN, default build/manyworlds).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs/media/boxworld_worlds.png}
camera=${2:-perspective}
size=(--width 400 --height 300)
if [ "$camera" = top ]; then size=(--width 320 --height 320); fi
bin=${MANYWORLDS_BIN:-build/manyworlds}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
inputs=()
for seed in 0 1 2 3 4 5; do
  "$bin" render --env box-world-complex --task-seed "$seed" --camera "$camera" \
    "${size[@]}" --out "$tmp/world_$seed.png" \
    --option floor_size=4 --option floor_size_max=8 --option num_boxes=1 \
    --option num_boxes_max=6 --option box_shapes=box,cylinder,sphere \
    --option box_size=0.1 --option box_size_max=0.3 --option random_colors=true >/dev/null
  inputs+=(-i "$tmp/world_$seed.png")
done
ffmpeg -loglevel error -y "${inputs[@]}" -filter_complex \
  "[0][1][2][3][4][5]xstack=inputs=6:layout=0_0|w0_0|w0+w1_0|0_h0|w0_h0|w0+w1_h0:fill=white" \
  -frames:v 1 "$tmp/grid.png"
mv "$tmp/grid.png" "$out"
echo "$out"
