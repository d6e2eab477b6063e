//! Move planning: how long a move takes (tₛ) and which ζ-a-tₛ shape it uses
//! (a) under every joint's speed limit. Pure numerics: it returns its own
//! [`PlanError`], which the app turns into a user-facing refusal.
//!
//! # Duration
//! Every joint follows `q0 + Δ_j·g(t)` with one shared profile g, so joint j
//! peaks at `|Δ_j|·max g′`. The move may use `ω_j` (rad/s) on joint j (the
//! caller derives it from the joint's `max_speed_rad_s`, the speed preset and
//! a safety margin), so the requirement is `r · max g′ ≤ 1` with the *time
//! ratio* `r = max_j |Δ_j|/ω_j` (seconds).
//! - Classic laws scale with their duration T: `max g′ = c/T` with c = 1
//!   (linear), 1.5 (cubic, trapezoid with T/3 ramps), 1.875 (quintic), so
//!   `T = max(ts_min, c·r)` is the shortest admissible duration, in closed form.
//! - ζ-a-tₛ is written in seconds, so its shape changes with tₛ and so does
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
//!
//! # Shape
//! The smooth stop a* while it is monotone, else the largest monotone a:
//! see [`shape_choice`].
//!
//! # Cost on the chip
//! Measured (bench row `app_plan_move`, n = 2, joint speeds 0.5 rad/s, moves
//! needing tₛ from 1.6 s to 20 s): median 192 000 cycles (12 ms at 16 MHz),
//! at most 201 000; the search this replaced took 1 756 000 (max 2 060 000).
//! A search evaluates 2–4 candidates for n = 2 (at most 12 for any n): each
//! builds its shape (~12 000–16 000 cycles) and estimates P from about one
//! evaluation of G with its first three log-derivatives (~14 000), and the
//! one returned gets one or two more. Larger n costs more where the creep
//! after t* must be searched too (n = 5: about 10 evaluations per search).
//! The frame that plans may overrun; the PWM keeps its last pulses meanwhile
//! and the plan clock counts frames, so this delays the move, it never jerks
//! it.

pub mod cells;
pub mod correction;
pub mod duration;
pub mod peak_rate;
pub mod plan_move;
pub mod request;
pub mod shape_choice;
