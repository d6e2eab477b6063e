//! Bounds of the normalized profiles on 16 cells of their time, for the
//! duration search of a correction superposed on a running move
//! ([`super::correction`]): per law whose profile only scales with its
//! duration (g(t) = f(t/T)), the value of f at the cell ends and the largest
//! |f′| and |f″| inside each cell. With them, a move's speed, acceleration
//! and position over any stretch of time are bounded by table reads and a
//! multiplication per joint, without evaluating the profile.
//!
//! The tables are constants, computed on the host (`tests/superpose.rs`
//! recomputes them from the laws' own f64 evaluation on 4000 points per
//! cell and checks every bound is at or above what it finds and at most
//! 2e-6 (relative) above); f at the cell ends is rounded to the nearest f32.
// The tables are printed from f64 computations with more digits than an
// f32 holds; the compiler rounds each to the nearest f32, which is what is
// wanted.
#![allow(clippy::excessive_precision)]

use crate::math::fixed::flash_u32;
use crate::math::real::Real;
use crate::motion::plan::LawKind;

/// Cells per profile.
pub const CELLS: usize = 16;

/// A law's cell bounds.
#[derive(Debug)]
pub struct CellTable {
    /// f(i/16), i = 0..=16: f is non-decreasing, so f on cell i lies
    /// between `f[i]` and `f[i + 1]`.
    pub f: [f32; CELLS + 1],
    /// max f′ on cell i (f′ ≥ 0).
    pub v: [f32; CELLS],
    /// max |f″| on cell i.
    pub a: [f32; CELLS],
}

/// The bits of a table entry: the tables live in flash on the AVR (read
/// with `lpm`), not in RAM.
#[inline(always)]
fn bits(p: &f32) -> u32 {
    // SAFETY: f32 and u32 have the same size and alignment; the pointer is
    // only read, through `flash_u32`.
    flash_u32(unsafe { &*(p as *const f32).cast::<u32>() })
}

impl CellTable {
    /// f at cell boundary i (1 from the end on).
    #[inline]
    pub fn f_at<R: Real>(&self, i: usize) -> R {
        match self.f.get(i) {
            Some(p) => R::from_f32(f32::from_bits(bits(p))),
            None => R::ONE,
        }
    }

    /// (max f′, max |f″|) over cells lo..hi (0 for cells past the end).
    pub fn max_over<R: Real>(&self, lo: usize, hi: usize) -> (R, R) {
        let (mut v, mut a) = (0u32, 0u32);
        let mut i = lo;
        while i < hi.min(CELLS) {
            // Non-negative floats order like their bit patterns.
            if let (Some(vi), Some(ai)) = (self.v.get(i), self.a.get(i)) {
                v = v.max(bits(vi));
                a = a.max(bits(ai));
            }
            i += 1;
        }
        (R::from_f32(f32::from_bits(v)), R::from_f32(f32::from_bits(a)))
    }
}

/// The table of a law whose profile scales with its duration; `None` for
/// the papers' ζ-a-tₛ and the linear law (which start with a velocity or
/// change shape with tₛ, so they are not superposed).
pub fn cell_table(kind: LawKind) -> Option<&'static CellTable> {
    match kind {
        LawKind::Zat => Some(&ZAT),
        LawKind::Quintic => Some(&QUINTIC),
        LawKind::Cubic => Some(&CUBIC),
        LawKind::Trapezoid => Some(&TRAPEZOID),
        LawKind::ZatPaper | LawKind::Linear => None,
    }
}

/// The time-scaled ζ-a-tₛ ([`crate::motion::scaled`]).
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
pub static ZAT: CellTable = CellTable {
    f: [
        0.0,
        1.017_3e-5,
        0.002_638_296,
        0.017_914_305,
        0.050_921_763,
        0.103_126_893,
        0.175_623_673,
        0.268_480_609,
        0.379_303_05,
        0.502_133_513,
        0.627_550_44,
        0.744_472_373,
        0.843_110_577,
        0.917_526_599,
        0.966_471_862,
        0.992_455_781,
        1.0,
    ],
    v: [
        1.805_266e-3,
        0.118_536_5,
        0.381_101_9,
        0.678_421_8,
        0.995_335_8,
        1.325_159,
        1.640_208,
        1.890_225,
        2.014_726,
        2.020_156,
        1.968_211,
        1.746_448,
        1.393_917,
        0.984_359_8,
        0.589_087_3,
        0.254_891_7,
    ],
    a: [
        0.262_602_3,
        3.494_33,
        4.590_283,
        4.913_399,
        5.215_13,
        5.300_47,
        5.265_643,
        4.678_698,
        3.153_371,
        2.203_538,
        4.768_389,
        6.306_499,
        6.636_935,
        6.602_956,
        5.920_237,
        4.727_918,
    ],
};

/// 10τ³ − 15τ⁴ + 6τ⁵.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
pub static QUINTIC: CellTable = CellTable {
    f: [
        0.0,
        0.002_218_246,
        0.016_052_246,
        0.048_768_997,
        0.103_515_625,
        0.180_006_027,
        0.275_207_52,
        0.384_027_481,
        0.5,
        0.615_972_519,
        0.724_792_48,
        0.819_993_973,
        0.896_484_375,
        0.951_231_003,
        0.983_947_754,
        0.997_781_754,
        1.0,
    ],
    v: [
        0.102_996_9,
        0.358_886_8,
        0.696_258_6,
        1.054_688,
        1.384_736,
        1.647_95,
        1.816_865,
        1.875_001,
        1.875_001,
        1.816_865,
        1.647_95,
        1.384_736,
        1.054_688,
        0.696_258_6,
        0.358_886_8,
        0.102_996_9,
    ],
    a: [
        3.076_173, 4.921_876, 5.712_892, 5.773_504, 5.625_001, 4.833_985, 3.515_626, 1.845_704, 1.845_704, 3.515_626,
        4.833_985, 5.625_001, 5.773_504, 5.712_892, 4.921_876, 3.076_173,
    ],
};

/// 3τ² − 2τ³.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
pub static CUBIC: CellTable = CellTable {
    f: [
        0.0,
        0.011_230_469,
        0.042_968_75,
        0.092_285_156,
        0.156_25,
        0.231_933_594,
        0.316_406_25,
        0.406_738_281,
        0.5,
        0.593_261_719,
        0.683_593_75,
        0.768_066_406,
        0.843_75,
        0.907_714_844,
        0.957_031_25,
        0.988_769_531,
        1.0,
    ],
    v: [
        0.351_562_6,
        0.656_250_7,
        0.914_063_5,
        1.125_001,
        1.289_063,
        1.406_251,
        1.476_563,
        1.500_001,
        1.500_001,
        1.476_563,
        1.406_251,
        1.289_063,
        1.125_001,
        0.914_063_5,
        0.656_250_7,
        0.351_562_6,
    ],
    a: [
        6.000_006, 5.250_006, 4.500_005, 3.750_004, 3.000_003, 2.250_003, 1.500_002, 0.750_001, 0.750_001, 1.500_002,
        2.250_003, 3.000_003, 3.750_004, 4.500_005, 5.250_006, 6.000_006,
    ],
};

/// Accelerate over the first third, cruise, brake over the last.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
pub static TRAPEZOID: CellTable = CellTable {
    f: [
        0.0,
        0.008_789_062,
        0.035_156_25,
        0.079_101_562,
        0.140_625,
        0.219_726_562,
        0.312_5,
        0.406_25,
        0.5,
        0.593_75,
        0.687_5,
        0.780_273_438,
        0.859_375,
        0.920_898_438,
        0.964_843_75,
        0.991_210_938,
        1.0,
    ],
    v: [
        0.281_250_3,
        0.562_500_6,
        0.843_750_9,
        1.125_001,
        1.406_251,
        1.500_001,
        1.500_001,
        1.500_001,
        1.500_001,
        1.500_001,
        1.500_001,
        1.406_251,
        1.125_001,
        0.843_750_9,
        0.562_500_6,
        0.281_250_3,
    ],
    a: [
        4.500_005, 4.500_005, 4.500_005, 4.500_005, 4.500_005, 4.500_005, 0.0, 0.0, 0.0, 0.0, 4.500_005, 4.500_005,
        4.500_005, 4.500_005, 4.500_005, 4.500_005,
    ],
};
