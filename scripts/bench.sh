#!/usr/bin/env bash
# The benchmark command: builds the product firmware and the bench firmware,
# runs the bench in simavr (cycle-exact) and writes BENCHMARKS.md.
#   scripts/bench.sh            # writes BENCHMARKS.md at the repository root
#   scripts/bench.sh OUT.md     # writes elsewhere
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
OUT=${1:-BENCHMARKS.md}
TARGET=${CARGO_TARGET_DIR:-target}
echo "== building firmware and bench firmware"
cargo avr
FW=$TARGET/avr-none/release/touch-arm.elf
BENCH=$TARGET/avr-none/release/bench.elf
for elf in "$FW" "$BENCH"; do
    python3 ../shared/tools/stackarg_lint.py "$elf" | tail -1
done
echo "== running the bench in simavr"
RAW=$(mktemp)
trap 'rm -f "$RAW"' EXIT
cargo run --release -q -p hal-sim --bin avr-run -- "$BENCH" 300 >"$RAW" || { echo "bench did not finish:"; tail -20 "$RAW"; exit 1; }

echo "== drawing the UI demo on the chip (ui-demo firmware, decoded bus)"
UI=$(mktemp)
trap 'rm -f "$RAW" "$UI"' EXIT
cargo test -q -p hal-sim --test ui_firmware -- --nocapture >"$UI" 2>&1 || { echo "ui_firmware failed:"; tail -20 "$UI"; exit 1; }
echo "== the product firmware's stack in its busiest session (painted in simavr)"
cargo test -q -p hal-sim --test firmware_e2e stack_stays_within_budget -- --nocapture >>"$UI" 2>&1 || { echo "firmware_e2e failed:"; tail -20 "$UI"; exit 1; }

python3 - "$RAW" "$FW" "$BENCH" "$OUT" "$UI" <<'PY'
import math, re, struct, subprocess, sys
raw, fw, bench, out, ui = sys.argv[1:]
lines = []
for l in open(raw, errors="replace"):
    l = re.sub(r"\x1b\[[0-9;]*m", "", l).strip().rstrip(".").strip()
    if l:
        lines.append(l)
B = {}
I = {}
order = []
for l in lines:
    f = l.split()
    if f[0] == "B" and len(f) == 6:
        B[f[1]] = list(map(int, f[2:])); order.append(f[1])
    elif f[0] == "I" and len(f) == 5:
        I[f[1]] = list(map(int, f[2:]))
overhead = next(int(l.split()[1]) for l in lines if l.startswith("O "))
stack_hw, stack_free = next(map(int, l.split()[1:3]) for l in lines if l.startswith("S "))

def f32(b): return struct.unpack("<f", struct.pack("<I", int(b)))[0]

# Accuracy of the chip's values against f64 (SPEC §5 in log space).
wg = wv = wp = 0.0; end_ours = end_paper = 0.0; n_pts = 0
for l in lines:
    if not l.startswith("A "):
        continue
    ts, a, n, t, g, r, pg = (f32(v) for v in l.split()[1:])
    L = math.log(n); u = t + ts / t - 1
    lnq = lambda w: -math.log(math.expm1(L * w))
    gr = 1.0 if t >= ts else math.exp(L * (t - ts) + lnq(u - a) - lnq(ts - a))
    q = 1 / math.expm1(L * (u - a))
    vr = gr * (L - L * (1 - ts / (t * t)) * (1 + q))
    wg = max(wg, abs(g - gr)); wv = max(wv, abs(r - vr) / max(1, abs(vr)))
    wp = max(wp, abs(pg - gr)); n_pts += 1
    if t == ts:
        end_ours = max(end_ours, abs(g - 1)); end_paper = max(end_paper, abs(pg - 1))

def sizes(elf):
    s = {}
    for l in subprocess.run(["avr-size", "-A", elf], capture_output=True, text=True).stdout.splitlines():
        p = l.split()
        if len(p) >= 2 and p[0].startswith(".") and p[1].isdigit():
            s[p[0]] = int(p[1])
    return s

def budget(name):
    for l in open("memory.x"):
        l = l.strip()
        if l.startswith("__budget_" + name):
            v = l.split("=")[1].split(";")[0].strip()
            return int(v[:-1]) * 1024 if v.endswith("K") else int(v)

fs, bs = sizes(fw), sizes(bench)
flash = lambda s: s.get(".text", 0) + s.get(".data", 0)
ram = lambda s: s.get(".data", 0) + s.get(".bss", 0)

desc = {
    "f32_mul": "f32 multiply (avr-libc)", "f32_add": "f32 add (avr-libc)", "f32_div": "f32 divide (avr-libc)",
    "f32_mul_x10": "10 chained f32 multiplies", "f32_add_x10": "10 chained f32 adds", "f32_lt": "f32 compare",
    "f32_to_i32": "f32 → i32", "i32_to_f32": "i32 → f32", "u32_mul": "u32 × u32 (libgcc)",
    "u64_mul_hi": "u64 product, high word (compiler-builtins `__muldi3`)",
    "avrlibc_exp": "avr-libc `exp`", "avrlibc_log": "avr-libc `log`",
    "exp": "`exp` (math::exp, integer core)", "expm1": "`expm1` (math::exp, integer core)",
    "ln": "`ln` (math::exp, integer core)", "libm_powf": "`libm::powf` (Rust libm crate)",
    "g": "ζ-a-tₛ G alone", "g_rate": "ζ-a-tₛ G and G′",
    "sample3": "`MultiPlan::sample`: 3 joints, positions + velocities (rad)",
    "frame": "**50 Hz frame**: `ServoTrack::frame`, 3 joints, time-scaled ζ-a-tₛ G + G′ → pulse widths + speed check",
    "frame_zat_paper": "frame, the papers' ζ-a-tₛ (tₛ in seconds)",
    "frame_superposed": "frame with a correction superposed: two ζ-a-tₛ terms → pulse widths",
    "app_replan": "**a re-plan mid-move**: correction superposed on the running move (`ServoTrack::replan`: cell bounds, duration search, in place)",
    "app_plan_move_paper": "the app's plan per touch for `law zat-paper` (tₛ search for the speed bound, a*, the largest G″ for the acceleration)",
    "frame_generic": "same frame via `MultiPlan::sample` + `ServoMap::angle_to_pulse` ×3",
    "frame_linear": "frame, linear law", "frame_cubic": "frame, cubic law",
    "frame_quintic": "frame, quintic law", "frame_trapezoid": "frame, trapezoid law",
    "paper_frame": "naive printed ζ form, 3 joints, position only (`libm::powf`)",
    "plan": "**plan**: touch map + pose (IK) + `Shape::smooth_stop` (a*) + `MultiPlan::with_law` with checks",
    "plan_generic": "same plan via `smooth_stop_a` + `MultiPlan::new` (shape and checks built twice)",
    "plan_map": "plan step: touch map (`Calibration::map`)",
    "plan_pose": "plan step: pose (`pose_for_point`: α, workspace, IK)",
    "plan_ik2": "`ik2` alone (its own direction arctangent)",
    "plan_alpha": "α alone (`workspace::alpha`)",
    "plan_a_star": "`smooth_stop_a` alone",
    "shape_new": "`Shape::new` (a = a*)",
    "shape_smooth_stop": "plan step: `Shape::smooth_stop` (a*, shape, monotonicity)",
    "check_monotone": "`Shape::check_monotone` from scratch",
    "multiplan_new": "`MultiPlan::new` (shape + checks + copies)",
    "sqrt": "`sqrt` (avr-libc)",
    "avrlibc_atan2": "avr-libc `atan2`",
    "atan2": "`atan2` (math::atan, integer core)",
    "acos": "`acos` (avr-libc; unused, the IK takes atan2)",
    "via_solve": "**via point**, closed form + ζ + ζ_v",
    "via_new": "`ViaPlan::new` alone (two shapes, r = G(t_v), S_v)",
    "via_zeta": "`zat::zeta` from scratch (ViaPlan's ζ reuse the shape)",
    "via_paper": "via point, the paper's iteration (tol 1e-5)",
    "app_plan_move": "**the app's plan per touch** (`planner::plan_move`: time-scaled ζ-a-tₛ, closed-form tₛ for speed and acceleration, checks)",
    "touch_sample": "**touch sample**: 5 × (X, Y, z1, z2) ADC reads with settle times, shared pins lent and restored",
}
targets = {"frame": 8000, "plan": 20000, "via_solve": 20000}

o = []
o.append("# Benchmarks\n")
o.append("Generated by `scripts/bench.sh` (the benchmark command): it builds the product firmware and the")
o.append("bench firmware (`src/bin/bench.rs`), runs the bench in simavr as an ATmega2560 at 16 MHz and")
o.append("writes this file. Every figure is a CPU cycle count, which simavr reproduces exactly.\n")
o.append("## Method\n")
o.append(f"- Each routine runs 15 times on varied inputs (frame times spread over the move, end included;")
o.append("  touch points, durations, via values); the table gives median, min and max cycles.")
o.append("- Cycles come from Timer1 (prescaler 1, exact modulo 2¹⁶) and Timer3 (prescaler 256, picks the")
o.append(f"  number of Timer1 wraps), no interrupts (`src/board/cycles.rs`). The stamp overhead ({overhead} cycles,")
o.append("  measured at boot on an empty section) is subtracted. Inputs pass through `black_box` after the")
o.append("  first stamp and results before the second, so the work can be neither hoisted nor sunk; that")
o.append("  costs a few cycles and stays in the figures.")
o.append("- Stack: free RAM is painted with 0xC5 before each routine (`src/board/stack.rs`); the stack column")
o.append("  is the high-water mark from the top of RAM while it ran, harness frames included.")
o.append("- Accuracy: the bench prints the chip's f32 G, G′ and the printed ζ form's G for 35 parameter sets")
o.append("  × 8 times as bit patterns, and its `ln`, `atan2` and split square root on sweeps; this script")
o.append("  compares them with f64. `tests/bench_elf.rs` does the same in the test command, checks the")
o.append("  chip's `exp`/`expm1`/`ln`/`atan2`/split root and its 15 plans (pose angles, a*) bit for bit")
o.append("  against the host, and enforces the frame budget and the stack budget.")
o.append("- Plan inputs: 15 touches across the screen with tₛ from 1.5 to 4 s, n = 2, a = a*. The last")
o.append("  (tₛ = 4) is refused: a* is monotone only while L·(tₛ − 1) ≤ 2, and the refusal computes the")
o.append("  overshoot peak by Newton's method; that is the max column of the plan rows.\n")
o.append("## Cycles\n")
o.append("| routine | median | min | max | target | stack B |")
o.append("| --- | ---: | ---: | ---: | ---: | ---: |")
for k in order:
    m, lo, hi, st = B[k]
    tgt = targets.get(k)
    # The issue states its targets for the median; the frame must also hold
    # at its worst (a frame that overran would delay the pulses), so it is
    # judged on its max.
    judged = hi if k == "frame" else m
    t = "" if tgt is None else (f"≤ {tgt} ✓" if judged <= tgt else f"≤ {tgt} ✗")
    o.append(f"| {desc.get(k, k)} | {m} | {lo} | {hi} | {t} | {st} |")
for k, (m, lo, hi) in I.items():
    o.append(f"| {k.replace('_', ' ')} (count) | {m} | {lo} | {hi} | | |")
if "frame" in B and "paper_frame" in B:
    o.append(f"\nThe frame costs {B['frame'][0] / 16000:.3f} ms at 16 MHz; the naive printed form takes "
             f"{B['paper_frame'][0] / B['frame'][0]:.1f}× as long for positions alone.\n")
o.append("## Accuracy on the chip (normalized units)\n")
o.append(f"Over {n_pts} samples of monotone shapes (tₛ ∈ [0.2, 10], n ∈ [1.1, 100], a down to 0.01 below u_min):\n")
o.append("| | worst error vs f64 | error at tₛ |")
o.append("| --- | ---: | ---: |")
o.append(f"| G (this evaluator) | {wg:.2e} | {end_ours:.1e} |")
o.append(f"| G′ (relative where \\|G′\\| > 1/s) | {wv:.2e} | |")
o.append(f"| printed ζ form, f32 with `libm::powf` | {wp:.2e} | {end_paper:.1e} |")
o.append("\nTarget: within 2e-6 and exact at tₛ.\n")

def ulp_err(got, want):
    w = abs(struct.unpack("<f", struct.pack("<f", want))[0])
    b = struct.unpack("<I", struct.pack("<f", w))[0]
    u = f32(b + 1) - w if w >= 2**-126 else 2**-149
    return abs(got - want) / u
wl = max((ulp_err(f32(v[1]), math.log(f32(v[0]))) for v in (l.split()[1:] for l in lines if l.startswith("L "))), default=0)
wt = max((ulp_err(f32(v[2]), math.atan2(f32(v[0]), f32(v[1]))) for v in (l.split()[1:] for l in lines if l.startswith("T "))), default=0)
wq = max((abs(f32(v[1]) + f32(v[2]) - math.sqrt(f32(v[0]))) / math.sqrt(f32(v[0])) for v in (l.split()[1:] for l in lines if l.startswith("Q "))), default=0)
o.append("The chip's own integer-core functions on their sweeps (the host tests sweep millions of")
o.append("arguments: `tests/chip_accuracy.rs`):\n")
o.append("| | worst error vs f64 | bound tested on the host |")
o.append("| --- | ---: | ---: |")
o.append(f"| `ln` | {wl:.2f} ulp | < 1 ulp |")
o.append(f"| `atan2` | {wt:.2f} ulp | < 1.5 ulp |")
o.append(f"| split √ (s + c) | {wq:.1e} relative | < 2⁻⁴⁶ |\n")
if "zat_time_over_quintic_permille" in I:
    m, lo, hi = I["zat_time_over_quintic_permille"]
    o.append("## Move time against the quintic\n")
    o.append(f"The time-scaled ζ-a-tₛ under the same speed and acceleration limits as the quintic, 15 moves at")
    o.append(f"3 rad/s from speed-bound (60 rad/s²) to acceleration-bound (1 rad/s²), planned on the chip: median")
    o.append(f"{m / 1000:.3f}×, from {lo / 1000:.3f}× (both at the 0.5 s floor) to {hi / 1000:.3f}× (goal ≤ 1.1×).\n")
o.append("## Display (ILI9341 over the 8-bit bus)\n")
o.append("Measured by `tests/ui_firmware.rs` on the `ui-demo` firmware, which draws the scripted screens of")
o.append("`ui::demo` through the real bus driver; the decoded picture equals the host rendering at every step.")
o.append("Step 0 is a full redraw; the others are the partial redraws of a change.\n")
ui_lines = [l.rstrip() for l in open(ui, errors="replace")]
table = []
take = False
for l in ui_lines:
    if l.startswith("step  cycles"):
        take = True
        continue
    if take:
        f = l.split()
        if len(f) == 5 and f[0].isdigit():
            table.append(f)
        else:
            take = False
o.append("| step | cycles | ms | pixels | commands |")
o.append("| ---: | ---: | ---: | ---: | ---: |")
for f in table:
    o.append("| " + " | ".join(f) + " |")
for l in ui_lines:
    if l.startswith("bus:") or l.startswith("stack:"):
        o.append("\n" + l.replace("bus:", "Bus:").replace("stack:", "UI stack:"))
o.append("")
o.append("## Memory\n")
o.append("| | product firmware (`touch-arm.elf`) | bench firmware | budget (memory.x) | goal |")
o.append("| --- | ---: | ---: | ---: | ---: |")
o.append(f"| flash (.text + .data) | {flash(fs)} B | {flash(bs)} B | {budget('flash')} B | 65536 B |")
o.append(f"| static RAM (.data + .bss) | {ram(fs)} B | {ram(bs)} B | {budget('static_ram')} B | |")
fw_stack = next((l.split(":")[1].split("B")[0].strip() for l in open(ui, errors="replace") if l.startswith("firmware stack high-water:")), "?")
o.append(f"| stack high-water | {fw_stack} B | {stack_hw} B | {budget('stack')} B | |")
o.append("\nProduct firmware stack: painted by the simavr harness at load and read after its busiest")
o.append("session (telemetry on, touches, re-plans, law change, `cal show`, STOP, `cal save`, status;")
o.append("`tests/firmware_e2e.rs`, which enforces the budget). Bench stack: all routines. The flash goal")
o.append("of 64 KiB is not met by the product firmware: attributed function by function (a build without")
o.append("inlining), about 36 KiB is the screen (drawing, layout, calibration flow, LCD driver, font), 30 KiB")
o.append("the math (integer-core exp/ln/atan2, ζ-a-tₛ, via, classic laws, IK, touch mapping), 17 KiB the")
o.append("app (state machine, planning policy, telemetry), 10 KiB the serial protocol and configuration")
met = "is met" if flash(fs) <= budget('flash') else "is not met"
o.append(f"store, the rest the board layer and runtime. The {budget('flash') // 1024} KiB budget {met}. AVR builds use")
o.append("`-inline-threshold=25` (`.cargo/config.toml`): 4.6 KiB less flash at no measured cost. The")
o.append("bench's static")
o.append("RAM holds its routine names (string literals live in RAM on the AVR unless placed in flash).\n")
o.append("## What made the frame fast\n")
o.append("- `math::exp`: `exp`/`expm1` with a 32-bit integer core (x·log₂e split exactly from the float's")
o.append("  bits, degree-5 polynomial for (2^f − 1)/f in Q1.31, 16×16 hardware products in inline")
o.append("  assembly) instead of avr-libc's `exp`; the same code runs on the host, bit for bit.")
o.append("- One profile evaluation per frame for all joints (G and G′ together); the SPEC §5 recipe with")
o.append("  L/t formed once and reused; u′ formed as (t − √tₛ)(t + √tₛ)/t² so G′ stays accurate near the pole.")
o.append("- `ServoTrack`: pulse = base + span·g in 32-bit fixed point per joint (servo::map's mapping with")
o.append("  its clamps folded into one window); the speed check is one comparison of |g′| with the")
o.append("  tightest joint's limit; joint velocities in rad/s only on request.\n")
o.append("## What made plan and via faster\n")
o.append("Before this work (same inputs): plan 57 771 cycles median, via 64 138. The target column")
o.append("judges the median (the frame: its max). The plan row's max is its one refused input")
o.append("(tₛ = 4: a* is not monotone there, and the refusal computes the overshoot peak by Newton's")
o.append("method for the error); the app never plans it, it picks the monotone limit instead.\n")
o.append("- `ln`, `exp`, `expm1` (math::exp) and `atan2` (math::atan) with 32-bit integer cores and")
o.append("  coefficient tables in flash, in place of avr-libc's `log`/`atan2` (~2 500 / ~3 000 cycles);")
o.append("  the 32×32 high product and the normalisation loops in inline assembly on the chip; the same")
o.append("  results on host and chip, checked bit for bit. `atan2`: 56 degree-3 minimax pieces.")
o.append("- Float comparisons that are library calls (~100 cycles) replaced where the operands are")
o.append("  known not to be NaN by integer tests on the bits (`Real::le_num`, `lt_num`, `is_positive`,")
o.append("  `eq_num`, `twice`), and `Real::barrier` where LLVM would run a float operation of one arm")
o.append("  of an `if` on both paths.")
o.append("- `Shape::smooth_stop(tₛ, n)`: a*, the shape and its monotonicity from one ln tₛ and one")
o.append("  square root (ln 2 is a constant, equal to the chip's `ln(2)` to the bit); monotonicity is")
o.append("  free where t* ≥ tₛ ⇔ L·(tₛ − 1) ≤ 2.")
o.append("- `Shape::new`: √tₛ split from the integer residual tₛ − s², u_min and δ from that one root,")
o.append("  the pole test without expm1, Q_s formed only at t = tₛ, finiteness checked once, the shape")
o.append("  built in place (no struct copies); `MultiPlan::with_law` writes the plan in place.")
o.append("- Via: both shapes built in place from parameters checked once, ln n shared when n_v = n;")
o.append("  ζ and ζ_v from the shape's L and 1 − n^(a − tₛ), one logarithm each.")
o.append("- Pose: the IK's shoulder direction is α (π − α left of centre), not a second arctangent; with")
o.append("  l2 = l3 the elbow angle is twice a half-angle arctangent; only the smaller of 1 ± c is formed,")
o.append("  and the reach slack only when a point is about to be refused.")
o.append("- The app's plan per touch: the peak rate of g′ by safeguarded Newton on G″ = 0 (exact to")
o.append("  1e-4, never below the true peak) instead of a grid and golden section, and the duration by")
o.append("  Newton on ln(ratio·P) with d ln P/dtₛ from the envelope theorem: 2–4 candidates for n = 2")
o.append("  (was 1 756 000 cycles median, 8 candidates of 32 evaluations each).")
o.append("- avr-libc's `memcpy`/`memset` linked in place of compiler-builtins' generic ones (which cost")
o.append("  ~500 cycles per struct copy).")
o.append("- Variable shifts in the integer cores go through `math::fixed::shr`/`shl`: LLVM speculates a shift")
o.append("  into the other arm of an `if` with a wrapped amount, and its AVR shift loop then runs 255 times.")
open(out, "w").write("\n".join(o) + "\n")
print(f"wrote {out}")
PY
