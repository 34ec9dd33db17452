#!/usr/bin/env bash
# The main job: install dependencies, build manyworlds (Release), then
#   1. roll out the scripted policies over MT10 (10 variations of each of the
#      10 tasks) and print the per-task success table,
#   2. render one scripted episode of every MT10 task to MP4,
#   3. train multi-task SAC on three point-navigation goals (a few minutes on
#      two cores) and print its per-task success table.
# Everything lands in runs/main/ (MANYWORLDS_OUT_DIR to change). Extra
# arguments are overrides for the training config, e.g.
# `scripts/main.sh experiment.steps_per_task=2000`. Idempotent: a second run
# starts the training afresh. MANYWORLDS_BUILD_DIR picks another build
# directory (default build/).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${MANYWORLDS_BUILD_DIR:-build}
out_dir=${MANYWORLDS_OUT_DIR:-runs/main}
mw="$build_dir/manyworlds"

bash scripts/setup.sh
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j"$(nproc)" --target manyworlds
mkdir -p "$out_dir/videos"

echo
echo "== 1/3 Scripted policies on MT10 (10 variations per task) =="
"$mw" rollout --env mt10 --policy scripted --episodes 10 --threads "$(nproc)" | tee "$out_dir/mt10_scripted.txt"
"$mw" rollout --env mt10 --policy scripted --episodes 10 --threads "$(nproc)" --json > "$out_dir/mt10_scripted.json"

echo
echo "== 2/3 Rendering one scripted episode of each MT10 task =="
for task in reach push pick-place door-open drawer-open drawer-close \
            button-press-topdown peg-insert-side window-open window-close; do
  "$mw" render --env "$task" --policy scripted --camera front --width 480 --height 360 \
        --every 4 --fps 20 --out "$out_dir/videos/$task.mp4"
done

echo
echo "== 3/3 Training MT-SAC on three point-navigation goals =="
rm -rf "$out_dir/point_nav3_mtsac"
"$mw" train configs/point_nav3_mtsac.yaml experiment.run_dir="$out_dir/point_nav3_mtsac" "$@"

echo
echo "main: results in $out_dir/ (mt10_scripted.txt/.json, videos/*.mp4, point_nav3_mtsac/)"
