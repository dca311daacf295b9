#!/usr/bin/env bash
# Records the results a behaviour-preserving change must not alter, into OUT_DIR (compare two such folders with
# `diff -r`): the Mario replay's verification, every shipped card's text, the switch matrix, the autopilot's
# summaries at seeds 1-10 and 2-iteration training logs (the walk, and the squat with its handover episodes).
# Usage: scripts/golden.sh OUT_DIR [BIN]      (BIN defaults to build/treelearn; about 10 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/golden.sh OUT_DIR [BIN]}
bin=${2:-build/treelearn}
mkdir -p "$out"
"$bin" replay levels/mario/win.replay --verify > "$out/replay.txt" 2>&1 || true
for s in $(sed -n 's/^\[skill\.\([a-z_]*\)\].*/\1/p' assets/skills/tree.toml); do
  "$bin" eval "$s" --threads 2 > "$out/card.$s.txt" 2>&1 || true
done
"$bin" eval switches --threads 2 > "$out/switches.txt" 2>&1 || true
for seed in 1 2 3 4 5 6 7 8 9 10; do
  "$bin" play levels/mario --autopilot --seed "$seed" --summary "$out/autopilot.$seed.txt" > /dev/null 2>&1 || true
done
models=$(mktemp -d)
cp assets/skills/*.onnx assets/skills/*.policy.bin "$models"/
for s in walk squat; do
  rm -rf "$out/train.$s"
  "$bin" train "$s" --steps 1 --seed 3 --threads 2 --run-dir "$out/train.$s" --models-dir "$models" \
    --eval-every 1 --eval-episodes 4 > /dev/null 2>&1 || true
  steps=$(awk -F, 'NR==2{print $2}' "$out/train.$s/log.csv" 2>/dev/null || echo 0)
  rm -rf "$out/train.$s"
  "$bin" train "$s" --steps $((2 * steps)) --seed 3 --threads 2 --run-dir "$out/train.$s" --models-dir "$models" \
    --eval-every 1 --eval-episodes 4 > /dev/null 2>&1 || true
  # wall-clock columns differ run to run: keep the rest
  python3 - "$out/train.$s/log.csv" > "$out/train.$s.csv" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
drop = {i for i, h in enumerate(rows[0]) if h in ("wall_s", "steps_per_s", "rollout_physics_s", "inference_s", "update_s")}
for r in rows: print(",".join(v for i, v in enumerate(r) if i not in drop))
PY
  rm -rf "$out/train.$s"
done
rm -rf "$models"
echo "golden results in $out"
