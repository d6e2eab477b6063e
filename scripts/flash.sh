#!/usr/bin/env bash
# Flashes a firmware ELF onto an Arduino Mega 2560 over its USB serial port,
# then opens a serial console at 115200 baud: ravedude (Ravedude.toml: the
# Mega's stock bootloader, avrdude -c wiring -p atmega2560 -b 115200).
#
#   scripts/flash.sh [--port DEV] [--no-console] [--dry-run] [FILE.elf]
#
# FILE defaults to target/avr-none/release/touch-arm.elf. The port comes from
# --port, else $TOUCH_ARM_PORT, else the first /dev/ttyACM* or /dev/ttyUSB*.
# --dry-run prints the exact ravedude command and changes nothing.
# The cargo runner is ravedude itself (.cargo/config.toml): `cargo avr-run`
# builds, flashes and opens the console on any OS, ravedude finding the Mega
# by its USB ids; this script stays for --dry-run and the port rules above,
# and flashes any ELF given (`scripts/flash.sh target/.../panel-probe.elf`).
set -euo pipefail
caller=$PWD
cd "$(dirname "$0")/.."

port=${TOUCH_ARM_PORT:-}
dry=0
console=1
elf=""
while [ $# -gt 0 ]; do
    case "$1" in
        --port) port=${2:?--port needs a device}; shift 2 ;;
        --port=*) port=${1#--port=}; shift ;;
        --dry-run) dry=1; shift ;;
        --no-console) console=0; shift ;;
        -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        -*) echo "flash: unknown option $1 (see --help)" >&2; exit 2 ;;
        *) elf=$1; shift ;;
    esac
done
# A path given is the caller's (cargo passes one relative to where it runs).
case "$elf" in
    "") elf=target/avr-none/release/touch-arm.elf ;;
    /*) ;;
    *) elf=$caller/$elf ;;
esac
if [ ! -f "$elf" ]; then
    echo "flash: $elf not found: build the firmware first with \`cargo avr\`" >&2
    exit 1
fi
if [ -z "$port" ]; then
    for p in /dev/ttyACM* /dev/ttyUSB*; do
        if [ -e "$p" ]; then port=$p; break; fi
    done
fi
cmd=(ravedude -P "${port:-/dev/ttyACM0}")
if [ "$console" -eq 1 ]; then cmd+=(-c); fi
cmd+=("$elf")
if [ "$dry" -eq 1 ]; then
    echo "${cmd[*]}"
    exit 0
fi
if [ -z "$port" ] || [ ! -e "$port" ]; then
    echo "flash: no board found${port:+ at $port}: connect the Mega 2560 by USB, or give its port with --port DEV or TOUCH_ARM_PORT" >&2
    exit 1
fi
command -v ravedude >/dev/null || { echo "flash: ravedude not installed (scripts/setup.sh installs it)" >&2; exit 1; }
command -v avrdude >/dev/null || { echo "flash: avrdude not installed (scripts/setup.sh installs it)" >&2; exit 1; }
echo "flash: ${cmd[*]}"
if [ "$console" -eq 0 ]; then
    # Ravedude.toml opens the console (open-console, for `cargo avr-run`):
    # without it, ravedude runs beside a copy that does not.
    case "$elf" in /*) ;; *) elf=$PWD/$elf ;; esac
    cmd[${#cmd[@]}-1]=$elf
    tmp=$(mktemp -d)
    grep -v '^open-console' Ravedude.toml >"$tmp/Ravedude.toml"
    cd "$tmp"
fi
exec "${cmd[@]}"
