//! The chip's f32 results against f64: the bench prints them as bit patterns
//! and the worst errors go into the report. G and G′ are judged against the
//! tests' oracle (`reference::zat`), the integer-core functions against the
//! host's f64 `ln`, `atan2` and `sqrt`.

use reference::zat::Zat;

use super::parse::BenchOutput;

/// Worst errors of one bench run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accuracy {
    /// Profile samples (`A` lines).
    pub samples: usize,
    /// Worst |G − f64| of the chip's evaluator.
    pub g: f64,
    /// Worst |G′ − f64| / max(1, |G′|).
    pub rate: f64,
    /// Worst |G − f64| of the printed ζ form in f32 with `libm::powf`.
    pub paper: f64,
    /// Worst |G − 1| at t = tₛ: the evaluator's, the printed form's.
    pub g_at_ts: f64,
    /// The same for the printed form.
    pub paper_at_ts: f64,
    /// Worst errors of `ln` and `atan2` in f32 ulps, of the split square root
    /// s + c relative to √x.
    pub ln_ulps: f64,
    /// Worst `atan2` error, f32 ulps.
    pub atan2_ulps: f64,
    /// Worst error of the split square root, relative.
    pub sqrt_rel: f64,
}

impl Accuracy {
    /// From the `A` (ts a n t G G′ printed-G), `L` (x ln), `T` (y x atan2)
    /// and `Q` (x s c) lines.
    pub fn of(bench: &BenchOutput) -> Result<Accuracy, String> {
        let mut acc = Accuracy {
            samples: 0,
            g: 0.0,
            rate: 0.0,
            paper: 0.0,
            g_at_ts: 0.0,
            paper_at_ts: 0.0,
            ln_ulps: 0.0,
            atan2_ulps: 0.0,
            sqrt_rel: 0.0,
        };
        for v in floats(bench, "A", 7)? {
            let [ts, a, n, t, g, r, pg] = [v[0], v[1], v[2], v[3], v[4], v[5], v[6]];
            let (gr, vr) = Zat::new(ts, a, n).g_rate(t);
            acc.g = acc.g.max((g - gr).abs());
            acc.rate = acc.rate.max((r - vr).abs() / vr.abs().max(1.0));
            acc.paper = acc.paper.max((pg - gr).abs());
            acc.samples += 1;
            if t == ts {
                acc.g_at_ts = acc.g_at_ts.max((g - 1.0).abs());
                acc.paper_at_ts = acc.paper_at_ts.max((pg - 1.0).abs());
            }
        }
        for v in floats(bench, "L", 2)? {
            acc.ln_ulps = acc.ln_ulps.max(ulp_err(v[1], v[0].ln()));
        }
        for v in floats(bench, "T", 3)? {
            acc.atan2_ulps = acc.atan2_ulps.max(ulp_err(v[2], v[0].atan2(v[1])));
        }
        for v in floats(bench, "Q", 3)? {
            let root = v[0].sqrt();
            acc.sqrt_rel = acc.sqrt_rel.max((v[1] + v[2] - root).abs() / root);
        }
        Ok(acc)
    }
}

/// The `tag` lines' f32 bit patterns as f64 values, at least `n` per line.
fn floats(bench: &BenchOutput, tag: &str, n: usize) -> Result<Vec<Vec<f64>>, String> {
    bench
        .rows(tag)?
        .into_iter()
        .map(|row| {
            if row.len() < n {
                return Err(format!("a bench `{tag}` line has {} values, expected {n}", row.len()));
            }
            row.iter()
                .map(|&b| u32::try_from(b).map(|b| f64::from(f32::from_bits(b))))
                .collect::<Result<Vec<f64>, _>>()
                .map_err(|_| format!("a bench `{tag}` line has a value that is not 32 bits"))
        })
        .collect()
}

/// |got − want| in units of the f32 spacing at `want` (rounded to f32): the
/// step up from it, or the subnormal spacing 2⁻¹⁴⁹ below the normal range.
pub fn ulp_err(got: f64, want: f64) -> f64 {
    let w = (want as f32).abs();
    let ulp = if f64::from(w) >= f64::from(f32::MIN_POSITIVE) {
        f64::from(f32::from_bits(w.to_bits() + 1) - w)
    } else {
        2f64.powi(-149)
    };
    (got - want).abs() / ulp
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ulp_error_counts_f32_steps() {
        assert_eq!(ulp_err(1.0, 1.0), 0.0);
        // Above 1 the f32 step is 2⁻²³, below it 2⁻²⁴.
        assert_eq!(ulp_err(1.0 + 2f64.powi(-23), 1.0), 1.0);
        assert_eq!(ulp_err(-0.75, -0.75 - 2f64.powi(-25)), 0.5);
        // Subnormal: the step is 2⁻¹⁴⁹.
        assert_eq!(ulp_err(3.0 * 2f64.powi(-149), 2f64.powi(-149)), 2.0);
    }

    #[test]
    fn profile_errors_against_the_reference() {
        // tₛ = 2, a = −1, n = 2 at t = 1 (the chip's G and G′ three f32 steps
        // up from f64's) and at t = tₛ (G exact, G′ rounded to f32).
        let r = Zat::new(2.0, -1.0, 2.0);
        let f = |x: f64| x as f32;
        let up3 = |x: f64| f32::from_bits(f(x).to_bits() + 3);
        let (g1, v1, v2) = (r.g(1.0), r.rate(1.0), r.rate(2.0));
        let row = |v: [f32; 7]| format!("A {}\n", v.map(|x| x.to_bits().to_string()).join(" "));
        let text = row([2.0, -1.0, 2.0, 1.0, up3(g1), up3(v1), f(g1)])
            + &row([2.0, -1.0, 2.0, 2.0, 1.0, f(v2), 1.0])
            + &format!("L {} {}\n", f(2.0).to_bits(), f(2f64.ln()).to_bits())
            + &format!("T {} {} {}\n", f(1.0).to_bits(), f(1.0).to_bits(), f(std::f64::consts::FRAC_PI_4).to_bits())
            + &format!("Q {} {} {}\n", f(3.0).to_bits(), f(1.732_050_8).to_bits(), 0);
        let acc = Accuracy::of(&BenchOutput::parse(&text)).unwrap();
        assert_eq!(acc.samples, 2);
        let rel = |got: f32, want: f64| (got as f64 - want).abs() / want.abs().max(1.0);
        assert_eq!(acc.g, (up3(g1) as f64 - g1).abs());
        assert_eq!(acc.rate, rel(up3(v1), v1).max(rel(f(v2), v2)));
        assert_eq!(acc.paper, (f(g1) as f64 - g1).abs());
        assert!(acc.g > 2.0 * acc.paper && acc.paper > 0.0, "{acc:?}");
        assert_eq!((acc.g_at_ts, acc.paper_at_ts), (0.0, 0.0));
        // Correctly rounded f32 values: at most half an ulp.
        assert!(acc.ln_ulps <= 0.5 && acc.atan2_ulps <= 0.5, "{acc:?}");
        assert_eq!(acc.sqrt_rel, (1.732_050_8f32 as f64 - 3f64.sqrt()).abs() / 3f64.sqrt());
    }
}
