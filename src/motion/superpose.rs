//! Re-planning without a velocity step: a running move and the corrections
//! superposed on it ([`Superposed`]).
//!
//! A new target q_new at t_r while a move runs keeps the move and adds a
//! correction that starts at rest: q(t) = q_old(t) + (q_new − q_old_end)·g(t −
//! t_r). A profile that starts at rest (every law but linear) adds nothing to
//! the velocity at t_r, and one whose acceleration starts at 0 too (ζ-a-tₛ,
//! quintic) nothing to the acceleration, so the motion stays continuous in
//! position, velocity and acceleration (cubic and trapezoid: in position
//! and velocity). The correction's duration is the planner's
//! ([`crate::motion::planner::correction`]).
//!
//! # Representation
//! Positions are kept relative to the motion's final target: term k adds
//! −Δ_k·(1 − g_k(t_k)) at its own local time t_k, which is −Δ_k until it
//! starts and exactly 0 from its end on. So the motion ends exactly on its
//! target, a finished term is dropped without a trace ([`Superposed::retire`]),
//! and adding a correction moves the target by Δ and adds −Δ, which is
//! −Δ·(1 − 0) at the correction's start: nothing moves at t_r.
//!
//! # Bounded state
//! At most [`ACTIVE`] terms run at once: the move and one correction. A
//! target that comes while two run is planned at once but starts when the
//! older one ends (it waits in a third slot; until then its −Δ cancels the
//! target's shift exactly), and a later target replaces a waiting one, which
//! has moved nothing yet. So a dragged finger never stacks terms, and the
//! only fold is exact: a finished term is dropped. The alternative, folding
//! two running terms into one polynomial from the current position,
//! velocity and acceleration, would act at once but changes the running
//! motion's shape and needs limit bounds of its own.

use crate::math::real::Real;
use crate::motion::plan::{JointLaw, MultiPlan, JOINTS};
use crate::motion::{all_finite, Sample, TrajError};

/// Terms that run at once: the move and one correction.
pub const ACTIVE: usize = 2;
/// Slots: the running terms and one waiting correction.
pub const TERMS: usize = ACTIVE + 1;

/// One profile of a superposed motion: Δ·g at its own local time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term<R> {
    /// The term's normalized profile.
    pub law: JointLaw<R>,
    /// Per joint: how far the term moves.
    pub delta: [R; JOINTS],
}

impl<R: Real> Term<R> {
    /// The term's duration, s.
    #[inline]
    pub fn duration(&self) -> R {
        self.law.duration()
    }
}

/// A move and the corrections superposed on it (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Superposed<R> {
    target: [R; JOINTS],
    /// Oldest first; a waiting correction is the last one present.
    terms: [Option<Term<R>>; TERMS],
}

impl<R: Real> Superposed<R> {
    /// A single move.
    pub fn new(plan: &MultiPlan<R>) -> Self {
        let mut m = Self::resting(plan.start());
        m.start(plan);
        m
    }

    /// No move: resting on `pose`.
    pub fn resting(pose: &[R; JOINTS]) -> Self {
        Superposed { target: *pose, terms: [None, None, None] }
    }

    /// Replaces everything with a single move.
    pub fn start(&mut self, plan: &MultiPlan<R>) {
        self.target = *plan.target();
        self.terms = [Some(Term { law: *plan.law(), delta: *plan.delta() }), None, None];
    }

    /// Drops every term: the motion rests where it ends (the caller holds
    /// the pose it last commanded).
    pub fn halt(&mut self) {
        self.terms = [None, None, None];
    }

    /// Where the motion ends, exactly.
    #[inline]
    pub fn target(&self) -> &[R; JOINTS] {
        &self.target
    }

    /// The running and waiting terms (empty slots `None`).
    #[inline]
    pub fn terms(&self) -> &[Option<Term<R>>; TERMS] {
        &self.terms
    }

    /// Terms present (running or waiting).
    pub fn len(&self) -> usize {
        self.terms.iter().filter(|t| t.is_some()).count()
    }

    /// No term left: the motion rests on its target.
    pub fn is_empty(&self) -> bool {
        self.terms.iter().all(Option::is_none)
    }

    /// The offset term k adds at its local time t: −Δ·(1 − g).
    #[inline]
    fn rest_weight(law: &JointLaw<R>, t: R) -> R {
        R::ONE - law.g(t)
    }

    /// Joint positions with term k at local time `t[k]`; exactly the target
    /// once every term has ended.
    pub fn positions(&self, t: &[R; TERMS]) -> [R; JOINTS] {
        let mut out = self.target;
        for (term, tk) in self.terms.iter().zip(t.iter()) {
            if let Some(term) = term {
                let w = Self::rest_weight(&term.law, *tk);
                for (o, d) in out.iter_mut().zip(term.delta.iter()) {
                    *o -= *d * w;
                }
            }
        }
        out
    }

    /// Positions and their first three derivatives (the sum of the terms').
    pub fn sample_full(&self, t: &[R; TERMS]) -> [Sample<R>; JOINTS] {
        let pos = self.positions(t);
        let mut out = [Sample::at_rest(R::ZERO); JOINTS];
        for (o, p) in out.iter_mut().zip(pos.iter()) {
            o.s = *p;
        }
        for (term, tk) in self.terms.iter().zip(t.iter()) {
            if let Some(term) = term {
                let g = term.law.g_derivs(*tk);
                for (o, d) in out.iter_mut().zip(term.delta.iter()) {
                    o.v += *d * g.v;
                    o.acc += *d * g.acc;
                    o.jerk += *d * g.jerk;
                }
            }
        }
        out
    }

    /// Adds a correction toward `target` under `law` (duration included) in
    /// slot `slot`: [`ACTIVE`] − 1 to run at once beside a single running
    /// term, [`ACTIVE`] to wait for the older of two (a waiting one is
    /// replaced). The caller starts the slot's clock at 0, or at minus the
    /// wait. Unchanged on error.
    pub fn add_correction(&mut self, target: &[R; JOINTS], law: &JointLaw<R>, slot: usize) -> Result<(), TrajError<R>> {
        let delta = self.correction_delta(target, slot)?;
        law.check_monotone()?;
        let Some(s) = self.terms.get_mut(slot) else { return Err(TrajError::NotFinite) };
        *s = Some(Term { law: *law, delta });
        self.target = *target;
        Ok(())
    }

    /// How far a correction in `slot` moves each joint to end on `target`:
    /// from the target without a waiting correction being replaced there
    /// (it has moved nothing).
    pub fn correction_delta(&self, target: &[R; JOINTS], slot: usize) -> Result<[R; JOINTS], TrajError<R>> {
        let mut base = self.target;
        if let Some(Some(old)) = self.terms.get(slot) {
            for (b, d) in base.iter_mut().zip(old.delta.iter()) {
                *b -= *d;
            }
        }
        let mut delta = [R::ZERO; JOINTS];
        for ((d, e), b) in delta.iter_mut().zip(target.iter()).zip(base.iter()) {
            *d = *e - *b;
        }
        let [d0, d1, d2] = delta;
        all_finite(&[d0, d1, d2])?;
        Ok(delta)
    }

    /// Drops every term that has ended at its local time `t[k]` (it adds
    /// exactly 0 from then on), moving the later ones down; returns the
    /// dropped slots as a bit mask (bit k: slot k before the call), so a
    /// caller moves what it keeps per term the same way.
    pub fn retire(&mut self, t: &[R; TERMS]) -> u8 {
        let mut gone = 0u8;
        let mut kept = 0;
        let terms = self.terms;
        for (k, (term, tk)) in terms.iter().zip(t.iter()).enumerate() {
            let Some(term) = term else { continue };
            if *tk < term.duration() {
                if let Some(slot) = self.terms.get_mut(kept) {
                    *slot = Some(*term);
                }
                kept += 1;
            } else {
                gone |= 1 << k;
            }
        }
        for slot in self.terms.iter_mut().skip(kept) {
            *slot = None;
        }
        gone
    }
}
