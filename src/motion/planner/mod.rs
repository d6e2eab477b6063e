//! Move planning: how long a move takes (tₛ) and, for the papers' ζ-a-tₛ,
//! which shape it uses (a), under every joint's speed and acceleration
//! limits; and how long a correction superposed on a running move takes
//! ([`correction`]). Pure numerics: it returns its own [`PlanError`](request::PlanError), which
//! the app turns into a user-facing refusal.
//!
//! # Duration
//! Every joint follows `q0 + Δ_j·g(t)` with one shared profile g, so joint j
//! peaks at `|Δ_j|·max g′` in speed and `|Δ_j|·max |g″|` in acceleration.
//! The move may use `ω_j` (rad/s) and `α_j` (rad/s²) on joint j (the caller
//! derives them from the joint's `max_speed_rad_s` and `max_accel_rad_s2`,
//! the speed preset and a safety margin), so the requirements are
//! `r · max g′ ≤ 1` and `r_a · max |g″| ≤ 1` with the *time ratios*
//! `r = max_j |Δ_j|/ω_j` (s) and `r_a = max_j |Δ_j|/α_j` (s²).
//! - The classic laws and the time-scaled ζ-a-tₛ ([`crate::motion::scaled`])
//!   scale with their duration T: `max g′ = c_v/T`, `max |g″| = c_a/T²`
//!   ([`peak_rate::law_ratios`]), so `T = max(ts_min, c_v·r, √(c_a·r_a))` is
//!   the shortest admissible duration, in closed form
//!   ([`plan_move::scaled_duration`]). The linear law steps its velocity at
//!   both ends: it honours the speed only.
//! - The papers' ζ-a-tₛ (`law zat-paper`) is written in seconds, so its shape changes with tₛ and so does
//!   `P(tₛ) = max g′`. P is found numerically ([`zat_peak_rate`](peak_rate::zat_peak_rate): Newton on
//!   G″ = 0 per hump, exact to 1e-4 and never below the true peak) and tₛ by
//!   a Newton search ([`duration`]) on `ln(r·P)` over `ln(tₛ − 1)`
//!   between `zat_ts_min` and `ts_max`, with the derivative of ln P from the
//!   envelope theorem. The answer is always a tₛ whose P was *verified*
//!   (computed exactly, not estimated); it is at most [`TS_SEARCH_TOL`](duration::TS_SEARCH_TOL) = 1 %
//!   longer than the shortest admissible tₛ (0.4 % on average; checked
//!   against bisection on dense f64 scans in the tests for n ∈ [1.3, 8]).
//!   With n = 2, P falls from 1.8/s at tₛ = 1.2 s to about 0.7/s at 4 s and
//!   then only slowly (0.51/s at 10 s, 0.27/s at 20 s): beyond the smooth
//!   stop's range a ζ-a-tₛ move is a hump of width ~√tₛ around t ≈ √tₛ, a
//!   near-stop and a slow creep, so large slow moves get long tₛ. P falls
//!   with tₛ for n ≥ 1.25; for smaller n it rises on part of [1, 2] s, and
//!   the search then returns a verified tₛ that need not be the shortest.
//!   Where the acceleration binds, a longer tₛ is then searched on its
//!   largest |G″| ([`peak_rate::zat_peak_acc`]; `plan_move::zat_paper`).
//!
//! # Shape
//! The smooth stop a* while it is monotone, else the largest monotone a:
//! see [`shape_choice`].
//!
//! # Cost on the chip
//! Measured (BENCHMARKS.md, rows `app_plan_move`, `app_plan_move_paper`,
//! `app_replan`): the closed form for the default law is about 25 000
//! cycles per plan (1.6 ms; the shape is built once per plan); the papers'
//! form searches: 2–4 candidates for its speed (n = 2) at 12 000–16 000
//! cycles to build a shape and ~14 000 to estimate its peak, then its
//! largest |G″| on two grids of 16 points refined on every hump, ~790 000
//! cycles in all; a correction superposed mid-move 60 000–165 000, well
//! inside a frame. A frame that overruns its period makes the PWM repeat
//! its last pulses once: at rest that only delays the move (the plan clock
//! counts frames), mid-move it holds the arm for a period.

pub mod cells;
pub mod correction;
pub mod duration;
pub mod peak_rate;
pub mod plan_move;
pub mod request;
pub mod shape_choice;
