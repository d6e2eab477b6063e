#!/usr/bin/env bash
# The benchmark command: builds the product firmware and the bench firmware,
# runs the bench in simavr (cycle-exact), measures the live bench's pacing
# (2 minutes of wall time) and writes BENCHMARKS.md (with xtask's
# `bench-report`, which holds the figures' parsing and the document).
#   scripts/bench.sh            # writes BENCHMARKS.md at the repository root
#   scripts/bench.sh OUT.md     # writes elsewhere
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh main
OUT=${1:-BENCHMARKS.md}
TARGET=${CARGO_TARGET_DIR:-target}
echo "== building firmware and bench firmware"
cargo avr
FW=$TARGET/avr-none/release/touch-arm.elf
BENCH=$TARGET/avr-none/release/bench.elf
echo "== post-link checks (code pointers, lpm data, stack-passed arguments)"
cargo test -q -p xtask --test firmware_elf
echo "== running the bench in simavr"
RAW=$(mktemp)
trap 'rm -f "$RAW"' EXIT
cargo run --release -q -p xtask --bin avr-run -- "$BENCH" 300 >"$RAW" || { echo "bench did not finish:"; tail -20 "$RAW"; exit 1; }

echo "== drawing the UI demo on the chip (ui-demo firmware, decoded bus)"
UI=$(mktemp)
trap 'rm -f "$RAW" "$UI"' EXIT
cargo test -q -p touch-arm-rig --test ui_firmware -- --nocapture >"$UI" 2>&1 || { echo "ui_firmware failed:"; tail -20 "$UI"; exit 1; }
echo "== the product firmware's stack in its busiest session (painted in simavr)"
cargo test -q -p touch-arm-rig --test firmware_e2e stack_stays_within_budget -- --nocapture >>"$UI" 2>&1 || { echo "firmware_e2e failed:"; tail -20 "$UI"; exit 1; }
echo "== the product firmware's frame budget in its busiest frames (simavr)"
cargo test -q -p touch-arm-rig --test frame_budget -- --nocapture --test-threads=1 >>"$UI" 2>&1 || { echo "frame_budget failed:"; tail -20 "$UI"; exit 1; }

echo "== the live bench's pacing (60 s idle, 60 s moving)"
PACING=$(mktemp)
trap 'rm -f "$RAW" "$UI" "$PACING"' EXIT
cargo run --release -q -p touch-arm-bench --bin touch-arm-live -- --pacing-report 60 --out "$PACING" || { echo "pacing report failed"; exit 1; }

echo "== touch for an unsteady hand (seeded Monte Carlo in the twin, 1000 taps a cell)"
TOUCH=$(mktemp)
trap 'rm -f "$RAW" "$UI" "$PACING" "$TOUCH"' EXIT
cargo run --release -q -p hal-sim --bin touch-mc -- --taps 1000 --out "$TOUCH" || { echo "touch-mc failed"; exit 1; }

cargo run --release -q -p xtask --bin bench-report -- \
    --bench-output "$RAW" --ui-output "$UI" --firmware "$FW" --bench-elf "$BENCH" --out "$OUT"
# The pacing and touch sections follow the generated document, each after one blank line.
printf '\n%s\n' "$(cat "$PACING")" >>"$OUT"
printf '\n%s\n' "$(cat "$TOUCH")" >>"$OUT"
