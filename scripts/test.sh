#!/usr/bin/env bash
# The README's test command: set-up, firmware build, then every host and
# simulator test (`cargo test` at the root runs the whole workspace).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
echo "== building the firmwares and examples (cargo avr: touch-arm, bench, ui-demo, far-call, examples/)"
cargo avr
echo "== building the mipidsi feature's example (cargo avr-mipidsi)"
cargo avr-mipidsi
echo "== running tests"
cargo test "$@"
