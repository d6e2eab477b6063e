#!/usr/bin/env bash
# The README's main job: set-up, build the firmware, run it in simavr, write out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
echo "== building firmware (cargo avr)"
cargo avr
echo "== running the firmware in simavr"
cargo run --release -q -p hal-sim --bin touch-arm-sim -- "$@"
