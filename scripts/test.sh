#!/usr/bin/env bash
# The README's test command: set-up, the hygiene gates (formatting, clippy,
# rustdoc), firmware build, then every host and simulator test (`cargo test`
# at the root runs the whole workspace).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
echo "== hygiene: rustfmt, clippy on host code, rustdoc (warnings denied)"
cargo +stable fmt --all --check
cargo +stable clippy --workspace --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc -p touch-arm --no-deps
echo "== building the firmwares and examples (cargo avr: touch-arm, bench, ui-demo, far-call, examples/)"
cargo avr
echo "== building the mipidsi feature's example (cargo avr-mipidsi)"
cargo avr-mipidsi
echo "== running tests"
cargo test "$@"
