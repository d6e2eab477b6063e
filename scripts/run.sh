#!/usr/bin/env bash
# The README's main job: set-up, build the firmware, run it in simavr, write out/.
#   scripts/run.sh [--xy X,Y | --raw X,Y]    one touch, results in out/
#       [--lcd C] [--wiring a|b|c]           the simulated display controller and touch wiring
#       [--grip open|close]                  a grip after the move
#       [--reset]                            the RESET pin once the arm has arrived
#       [--law LAW] [--path joint|line | --lift H] [--then X2,Y2@MS]
#                                            sent over serial before the touch:
#                                            --path line: along the straight line;
#                                            --lift H: through a via pose H higher
#   scripts/run.sh --live [--port P]         the live bench at http://127.0.0.1:P/
#       [--lcd C] [--wiring W]               (default 8080; Ctrl-C stops it), on
#                                            the shield --lcd/--wiring name
set -euo pipefail
cd "$(dirname "$0")/.."
# What this command needs, no more (no Chromium, npm or ravedude).
if [ "${1:-}" = "--live" ]; then bash scripts/setup.sh live; else bash scripts/setup.sh main; fi
echo "== building firmware (cargo avr)"
cargo avr
if [ "${1:-}" = "--live" ]; then
    shift
    echo "== the live bench: the firmware in simavr, paced to real time"
    # cargo run replaces itself with the bench, so Ctrl-C reaches it directly.
    exec cargo run --release -q -p touch-arm-bench --bin touch-arm-live -- "$@"
fi
echo "== running the firmware in simavr"
cargo run --release -q -p touch-arm-bench --bin touch-arm-sim -- "$@"
