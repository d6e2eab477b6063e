#!/usr/bin/env bash
# Flashes a firmware ELF onto an Arduino Mega 2560 over its USB serial port
# with avrdude (the stock stk500v2 "wiring" bootloader, 115200 baud).
#
#   scripts/flash.sh [--port DEV] [--dry-run] [FILE.elf]
#
# FILE defaults to target/avr-none/release/touch-arm.elf. The port comes from
# --port, else $TOUCH_ARM_PORT, else the first /dev/ttyACM* or /dev/ttyUSB*.
# --dry-run prints the exact avrdude command and changes nothing.
# Also the cargo runner for avr-none (`cargo run --release --target avr-none
# -Z build-std=core --features firmware --bin touch-arm`, alias `cargo flash`).
set -euo pipefail
cd "$(dirname "$0")/.."

port=${TOUCH_ARM_PORT:-}
dry=0
elf=""
while [ $# -gt 0 ]; do
    case "$1" in
        --port) port=${2:?--port needs a device}; shift 2 ;;
        --port=*) port=${1#--port=}; shift ;;
        --dry-run) dry=1; shift ;;
        -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        -*) echo "flash: unknown option $1 (see --help)" >&2; exit 2 ;;
        *) elf=$1; shift ;;
    esac
done
elf=${elf:-target/avr-none/release/touch-arm.elf}
if [ ! -f "$elf" ]; then
    echo "flash: $elf not found: build the firmware first with \`cargo avr\`" >&2
    exit 1
fi
if [ -z "$port" ]; then
    for p in /dev/ttyACM* /dev/ttyUSB*; do
        if [ -e "$p" ]; then port=$p; break; fi
    done
fi
hex="${elf%.elf}.hex"
cmd=(avrdude -p atmega2560 -c wiring -P "${port:-/dev/ttyACM0}" -b 115200 -D -U "flash:w:$hex:i")
if [ "$dry" -eq 1 ]; then
    echo "avr-objcopy -O ihex -R .eeprom $elf $hex"
    echo "${cmd[*]}"
    exit 0
fi
if [ -z "$port" ] || [ ! -e "$port" ]; then
    echo "flash: no board found${port:+ at $port}: connect the Mega 2560 by USB, or give its port with --port DEV or TOUCH_ARM_PORT" >&2
    exit 1
fi
command -v avrdude >/dev/null || { echo "flash: avrdude not installed (scripts/setup.sh installs it)" >&2; exit 1; }
avr-objcopy -O ihex -R .eeprom "$elf" "$hex"
echo "flash: ${cmd[*]}"
"${cmd[@]}"
