#!/usr/bin/env bash
# A wheel install behaves as the checkout: build the sdist and the wheel from it (python -m build), install the
# wheel in a fresh venv outside the checkout, plan copies of bundled instances there and compare the plan lines
# (stations, bound, best-known) with the checkout's `planner plan` of the same files.
# Usage: bash scripts/checks/check_wheel.sh [INSTANCE ...]   (default: polygon_b plant_1ha)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
names=("${@:-polygon_b plant_1ha}")
read -r -a names <<< "${names[*]}"
python3 -m venv "$work/buildenv" && "$work/buildenv/bin/pip" install -q build
"$work/buildenv/bin/python" -m build --outdir "$work/dist" "$root" > "$work/build.log" 2>&1 || { tail -20 "$work/build.log"; exit 1; }
python3 -m venv "$work/venv"
"$work/venv/bin/pip" install -q "$work"/dist/*.whl
mkdir "$work/run"
status=0
for name in "${names[@]}"; do
  cp "$root/instances/$name".* "$work/run/"  # the instance and the tables it names
  (cd "$work/run" && "$work/venv/bin/planner" plan "$name.json" > "$work/wheel_$name.txt" 2>&1) || true
  (cd "$root" && planner plan "instances/$name.json" > "$work/checkout_$name.txt" 2>&1) || true
  # the whole output, less the timings and the folder of the file
  strip() { sed -E 's/[0-9]+(\.[0-9]+)? s\b/T s/g; s/[0-9]+(\.[0-9]+)? (GiB|MiB)/M \2/g; s/instances\///g' "$1"; }
  if diff <(strip "$work/checkout_$name.txt") <(strip "$work/wheel_$name.txt"); then
    echo "$name: the wheel prints the checkout's plan lines ($(strip "$work/wheel_$name.txt" | wc -l) lines)"
    grep -E "^(stations:|best known|bound scope)" "$work/wheel_$name.txt" | cut -c1-160 || true
  else
    echo "$name: the wheel's plan differs from the checkout's (above)"; status=1
  fi
done
exit $status
