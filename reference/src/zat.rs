//! The ζ-a-tₛ profile G and its velocity G′ (method §7).
//!
//! G is the printed form's n^t·q(t) normalized by its value at tₛ, taken in
//! log space so that neither n^t nor n^u is formed (they overflow long before
//! G stops being meaningful):
//!
//! ```text
//! G(t)  = exp(L·(t − tₛ) + ln q(u(t)) − ln q(tₛ)),   u(t) = t + tₛ/t − 1,
//! q(w)  = 1/(e^(L·(w − a)) − 1),                       L = ln n,
//! G′(t) = G·(L − L·u′·(1 + q)),                        u′ = 1 − tₛ/t²
//! ```
//!
//! (the derivative by the quotient rule on n^(t − tₛ)·q(t)/q(tₛ)), with the
//! conventions of method §7.3 at the ends: G = 0 and G′ = 0 for t ≤ 0; at
//! t = tₛ, G = 1 and G′ is the left limit (the formula at tₛ); for t > tₛ,
//! G = 1 and G′ = 0.
//!
//! [`Zat::printed`] is the papers' own form (method §7.1), with ζ from its
//! printed definition and the powers formed directly: the check that the
//! normalized form is the papers' trajectory, where nothing overflows.

/// One ζ-a-tₛ profile: duration tₛ, shape a, base n (L = ln n kept).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Zat {
    ts: f64,
    a: f64,
    n: f64,
    l: f64,
}

impl Zat {
    /// The profile of duration `ts`, shape `a` and base `n`. No domain
    /// checks: outside the admissible domain (a ≥ u_min, n ≤ 1) the values
    /// are whatever the formula gives, NaN included.
    pub fn new(ts: f64, a: f64, n: f64) -> Zat {
        Zat { ts, a, n, l: n.ln() }
    }

    /// The duration tₛ.
    pub fn ts(&self) -> f64 {
        self.ts
    }

    /// q at w = u: 1/(n^(w − a) − 1).
    pub fn q(&self, w: f64) -> f64 {
        1.0 / (self.l * (w - self.a)).exp_m1()
    }

    /// G(t).
    pub fn g(&self, t: f64) -> f64 {
        self.g_rate(t).0
    }

    /// G′(t) (the left limit at tₛ).
    pub fn rate(&self, t: f64) -> f64 {
        self.g_rate(t).1
    }

    /// G′(tₛ⁻): the end velocity per unit of Δ (method §7.6).
    pub fn end_rate(&self) -> f64 {
        self.rate(self.ts)
    }

    /// The printed S(t) = q₀ ± n^(t − ζ)/|n^u − n^a| of a move from `q0` to
    /// `sf` (+ rising, − falling), S_f from tₛ on and q₀ up to 0.
    pub fn printed(&self, q0: f64, sf: f64, t: f64) -> f64 {
        let (ts, a, n) = (self.ts, self.a, self.n);
        if t <= 0.0 {
            return q0;
        }
        if t >= ts {
            return sf;
        }
        let m = n.powf(t - self.printed_zeta(q0, sf)) / (n.powf(t + ts / t - 1.0) - n.powf(a)).abs();
        if sf >= q0 {
            q0 + m
        } else {
            q0 - m
        }
    }

    /// ζ = tₛ − log_n(|S_f − q₀|·(n^tₛ − n^a)), as printed.
    pub fn printed_zeta(&self, q0: f64, sf: f64) -> f64 {
        self.ts - ((sf - q0).abs() * (self.n.powf(self.ts) - self.n.powf(self.a))).ln() / self.l
    }

    /// (G(t), G′(t)).
    pub fn g_rate(&self, t: f64) -> (f64, f64) {
        let (ts, a, l) = (self.ts, self.a, self.l);
        if t <= 0.0 {
            return (0.0, 0.0);
        }
        if t > ts {
            return (1.0, 0.0);
        }
        let u = t + ts / t - 1.0;
        let ln_q = |w: f64| -(l * (w - a)).exp_m1().ln();
        let g = if t == ts { 1.0 } else { (l * (t - ts) + ln_q(u) - ln_q(ts)).exp() };
        let du = 1.0 - ts / (t * t);
        (g, g * (l - l * du * (1.0 + self.q(u))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn g_is_the_printed_form_normalized() {
        for &(ts, a, n) in &[(2.0, -1.0, 2.0), (1.5, 0.2, 3.0), (5.0, 2.0, 1.5)] {
            let z = Zat::new(ts, a, n);
            for (q0, sf) in [(0.0, 1.0), (2.0, -1.5)] {
                for k in 1..100 {
                    let t = ts * k as f64 / 100.0;
                    // Relative to G where q₀ = 0; up to q₀'s rounding otherwise.
                    let (want, got) = (q0 + (sf - q0) * z.g(t), z.printed(q0, sf, t));
                    let tol = 1e-13 * (sf - q0).abs() * z.g(t) + 2.0 * f64::EPSILON * q0.abs();
                    assert!((got - want).abs() <= tol, "ts={ts} a={a} n={n} t={t}: {got} vs {want}");
                }
                assert_eq!((z.printed(q0, sf, 0.0), z.printed(q0, sf, ts)), (q0, sf));
            }
        }
        // ζ = 3 − log₂(0.7·(2³ − 2^1.5)) for a move of 0.7.
        let z = Zat::new(3.0, 1.5, 2.0).printed_zeta(0.2, 0.9);
        assert!((z - (3.0 - (0.7f64 * (8.0 - 2f64.powf(1.5))).log2())).abs() < 1e-15);
    }

    #[test]
    fn rate_is_the_derivative_of_g() {
        let z = Zat::new(3.0, 0.5, 2.0);
        for k in 1..60 {
            let t = 3.0 * k as f64 / 60.0;
            let h = 1e-5 * t.min(3.0 - t).max(1e-3);
            let fd = (z.g(t + h) - z.g(t - h)) / (2.0 * h);
            assert!((z.rate(t) - fd).abs() < 1e-7 * (1.0 + fd.abs()), "t={t}: {} vs {fd}", z.rate(t));
        }
    }

    #[test]
    fn ends_follow_the_method_conventions() {
        // a* = tₛ − log_n tₛ: the smooth stop, G′(tₛ⁻) = 0.
        let (ts, n) = (2.0f64, 2.0f64);
        let z = Zat::new(ts, ts - ts.ln() / n.ln(), n);
        assert_eq!(z.g_rate(0.0), (0.0, 0.0));
        assert_eq!(z.g_rate(-1.0), (0.0, 0.0));
        assert_eq!(z.g(ts), 1.0);
        assert!(z.rate(ts).abs() < 1e-15);
        assert_eq!(z.g_rate(ts * 1.01), (1.0, 0.0));
        // Another a: the left limit at tₛ is the formula, not 0.
        let z = Zat::new(ts, -1.0, n);
        let l = n.ln();
        let want = l - l * (1.0 - 1.0 / ts) * (1.0 + 1.0 / (l * (ts + 1.0)).exp_m1());
        assert!((z.rate(ts) - want).abs() < 1e-15);
        assert_eq!(z.q(ts), 1.0 / (l * (ts + 1.0)).exp_m1());
    }
}
