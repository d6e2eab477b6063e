//! Williams (2013)'s single polynomial through a via point, for comparison
//! with the via-point homotopy, and the maximum search the items share.

/// The 6th-order polynomial θ(t) = Σ c_k·t^k (k = 0..6) that starts at `q0`
/// and ends at `sf` at `ts` at rest with zero acceleration and passes
/// `theta_v` at `tv` (Williams, "Simplified robotics joint-space trajectory
/// generation with a via point using a single polynomial", J. Robotics 2013).
///
/// Written in τ = t/tₛ as the quintic plus the one degree-6 term that keeps
/// all six end conditions, θ = q0 + Δ(10τ³ − 15τ⁴ + 6τ⁵) + c·τ³(1 − τ)³,
/// with c fixing the via value: a closed form instead of a 7×7 solve.
/// `None` when `tv` is not inside (0, tₛ).
pub fn via_poly(q0: f64, theta_v: f64, sf: f64, tv: f64, ts: f64) -> Option<[f64; 7]> {
    if !(tv > 0.0 && tv < ts) {
        return None;
    }
    let d = sf - q0;
    let tau = tv / ts;
    let quintic = tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
    let bump = (tau * (1.0 - tau)).powi(3);
    let c = (theta_v - q0 - d * quintic) / bump;
    // τ³(1 − τ)³ = τ³ − 3τ⁴ + 3τ⁵ − τ⁶.
    let in_tau = [q0, 0.0, 0.0, 10.0 * d + c, -15.0 * d - 3.0 * c, 6.0 * d + 3.0 * c, -c];
    let mut out = [0.0; 7];
    let mut scale = 1.0;
    for (k, b) in in_tau.iter().enumerate() {
        out[k] = b / scale;
        scale *= ts;
    }
    Some(out)
}

/// (θ, θ′, θ″, θ‴) of the polynomial with ascending coefficients `c` at `t`.
pub fn poly_derivs(c: &[f64; 7], t: f64) -> [f64; 4] {
    let mut out = [0.0; 4];
    for (d, slot) in out.iter_mut().enumerate() {
        // Horner on the d-th derivative's coefficients k!/(k−d)!·c_k.
        let mut acc = 0.0;
        for k in (d..7).rev() {
            let falling: f64 = ((k - d + 1)..=k).map(|j| j as f64).product();
            acc = acc * t + falling * c[k];
        }
        *slot = acc;
    }
    out
}

/// The largest value of `f` on [lo, hi] and where it is: the best of `n`
/// even intervals, refined by golden-section search on the two intervals
/// around it (the value's error is then of the order of the rounding, since
/// f is flat at an interior maximum), and the ends themselves.
pub fn max_on(f: impl Fn(f64) -> f64, lo: f64, hi: f64, n: usize) -> (f64, f64) {
    let at = |i: usize| lo + (hi - lo) * i as f64 / n as f64;
    let best = (0..=n).map(|i| (i, f(at(i)))).fold((0, f64::NEG_INFINITY), |b, c| if c.1 > b.1 { c } else { b });
    let (mut a, mut b) = (at(best.0.saturating_sub(1)), at((best.0 + 1).min(n)));
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (b - r * (b - a), a + r * (b - a));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..200 {
        if b - a <= 1e-15 * (1.0 + b.abs()) {
            break;
        }
        if f1 < f2 {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + r * (b - a);
            f2 = f(x2);
        } else {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - r * (b - a);
            f1 = f(x1);
        }
    }
    let mid = 0.5 * (a + b);
    [(mid, f(mid)), (lo, f(lo)), (hi, f(hi)), (at(best.0), best.1)]
        .into_iter()
        .fold((mid, f64::NEG_INFINITY), |m, c| if c.1 > m.1 { c } else { m })
}
