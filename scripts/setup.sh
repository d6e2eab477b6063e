#!/usr/bin/env bash
# Idempotent set-up for a fresh Debian machine: installs what one command
# needs, and nothing when all of it is present.
#
#   scripts/setup.sh [main|live|flash|test]
#
#   main   the main job (scripts/run.sh): the AVR cross toolchain, simavr's C
#          build needs, a font for the plots, the pinned nightly with rust-src
#   live   the live bench (scripts/run.sh --live): main's, less the plots' font
#          (the page draws in the browser you open it in)
#   flash  a board (cargo avr-run, scripts/flash.sh): the AVR cross toolchain,
#          the nightly, avrdude, libudev and ravedude; no simavr
#   test   the test command (scripts/test.sh, .ci/run; the default): all of the
#          above, plus rustfmt and clippy on the stable toolchain and Debian's
#          chromium with the pinned playwright-core (npm) for the page test
#
# Times on a fresh machine: docs/developing.md, "Set-up".
set -euo pipefail
cd "$(dirname "$0")/.."

what=${1:-test}
# The AVR cross toolchain: cargo avr links with avr-gcc and avr-libc's libm.
AVR=(gcc-avr avr-libc binutils-avr)
# simavr-ffi builds simavr from C: make, a C compiler, clang (bindgen),
# pkg-config, libelf, zlib and libzstd.
SIMAVR=(libelf-dev zlib1g-dev libzstd-dev pkg-config clang libclang-dev make)
# The main job's plots (angles.png, path.png) find DejaVu Sans.
FONT=(fonts-dejavu-core)
# Flashing: avrdude; libudev-dev: ravedude's serial-port discovery links it,
# found by libudev-sys's build script through pkg-config (a fresh machine
# has no pkg-config: ravedude's install failed there without it).
FLASH=(avrdude libudev-dev pkg-config)
# chromium: the live bench's page test (hal-sim/bench/tests/live_page.rs).
BROWSER=(chromium)
case "$what" in
    main) APT_PKGS=("${AVR[@]}" "${SIMAVR[@]}" "${FONT[@]}") ;;
    live) APT_PKGS=("${AVR[@]}" "${SIMAVR[@]}") ;;
    flash) APT_PKGS=("${AVR[@]}" "${FLASH[@]}") ;;
    test) APT_PKGS=("${AVR[@]}" "${SIMAVR[@]}" "${FONT[@]}" "${FLASH[@]}" "${BROWSER[@]}") ;;
    -h|--help) sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "setup: unknown command '$what' (main, live, flash or test)" >&2; exit 2 ;;
esac
RAVEDUDE_VERSION=0.2.2
TOOLCHAIN=$(sed -n 's/^channel *= *"\(.*\)"/\1/p' rust-toolchain.toml)

missing=()
for p in "${APT_PKGS[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    cmd="apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ${missing[*]}"
    if [ "$(id -u)" -eq 0 ]; then
        echo "setup: installing ${missing[*]}"
        bash -c "$cmd" >/tmp/touch-arm-apt.log 2>&1 || { tail -20 /tmp/touch-arm-apt.log; exit 1; }
    elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
        echo "setup: installing ${missing[*]} (sudo)"
        sudo bash -c "$cmd" >/tmp/touch-arm-apt.log 2>&1 || { tail -20 /tmp/touch-arm-apt.log; exit 1; }
    else
        echo "setup: missing Debian packages: ${missing[*]}" >&2
        echo "setup: run as root:  sudo bash -c '$cmd'" >&2
        exit 1
    fi
fi

if ! command -v rustup >/dev/null 2>&1; then
    echo "setup: rustup not found; install Rust via rustup first" >&2
    exit 1
fi
if ! rustup toolchain list | grep -q "^$TOOLCHAIN"; then
    echo "setup: installing Rust $TOOLCHAIN (+rust-src)"
    rustup toolchain install "$TOOLCHAIN" --profile minimal --component rust-src
elif ! rustup component list --toolchain "$TOOLCHAIN" --installed 2>/dev/null | grep -q '^rust-src'; then
    rustup component add rust-src --toolchain "$TOOLCHAIN"
fi

# ravedude from the Rust package registry, with its own lock file (about 40 s
# to build on two cores, once per machine).
if [ "$what" = flash ] || [ "$what" = test ]; then
    if ! command -v ravedude >/dev/null 2>&1 || ! ravedude --version 2>/dev/null | grep -qw "v$RAVEDUDE_VERSION"; then
        echo "setup: installing ravedude $RAVEDUDE_VERSION (cargo install)"
        cargo install ravedude --version "$RAVEDUDE_VERSION" --locked --quiet
    fi
fi

[ "$what" = test ] || exit 0

# The hygiene gates of scripts/test.sh run rustfmt and clippy from the stable
# toolchain: the pinned nightly ships neither.
if ! rustup toolchain list | grep -q "^stable"; then
    echo "setup: installing Rust stable (+rustfmt, clippy)"
    rustup toolchain install stable --profile minimal --component rustfmt --component clippy
else
    for c in rustfmt clippy; do
        rustup component list --toolchain stable --installed 2>/dev/null | grep -q "^$c" || rustup component add "$c" --toolchain stable
    done
fi

# Playwright (playwright-core, pinned in hal-sim/bench/tests/browser/package-lock.json)
# drives Debian's chromium in the live page test; npm installs it into that
# folder's node_modules/. Node.js and npm come with the machine.
BROWSER_DIR=hal-sim/bench/tests/browser
want=$(sed -n 's/.*"playwright-core": "\([0-9.]*\)".*/\1/p' "$BROWSER_DIR/package.json")
have=$(sed -n 's/^ *"version": "\([0-9.]*\)".*/\1/p' "$BROWSER_DIR/node_modules/playwright-core/package.json" 2>/dev/null | head -1 || true)
if [ "$want" != "$have" ]; then
    command -v npm >/dev/null 2>&1 || { echo "setup: npm not found (Node.js 20+ with npm is needed for the page test)" >&2; exit 1; }
    echo "setup: installing playwright-core $want (npm ci in $BROWSER_DIR)"
    (cd "$BROWSER_DIR" && npm ci --no-audit --no-fund >/tmp/touch-arm-npm.log 2>&1) || { tail -20 /tmp/touch-arm-npm.log; exit 1; }
fi
