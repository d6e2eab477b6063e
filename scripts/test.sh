#!/usr/bin/env bash
# The README's test command: set-up, firmware build, then every host and
# simulator test (`cargo test` at the root runs the whole workspace).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
echo "== building the firmwares (cargo avr: touch-arm, bench, ui-demo, far-call)"
cargo avr
echo "== running tests"
cargo test "$@"
