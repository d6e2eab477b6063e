//! Machine-readable output for `armsim`: flat JSON objects and CSV rows, every
//! number with 17 significant digits (lossless for f64), non-finite as `null`.

use std::fmt::Write;

/// `v` with at least 15 significant digits and exactly enough to round-trip:
/// the shortest representation that reads back as the same f64 (16 or 17
/// digits where needed), padded to 15. Fixed notation for ordinary
/// magnitudes, scientific outside [1e-4, 1e15).
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return "null".into();
    }
    if v == 0.0 {
        return if v.is_sign_negative() { "-0.0".into() } else { "0.0".into() };
    }
    // Digits of the shortest round-trip form ("1.2345e-7" → 5).
    let shortest = format!("{v:e}");
    let mantissa = shortest.trim_start_matches('-').split('e').next().unwrap_or("");
    let digits = mantissa.chars().filter(char::is_ascii_digit).count();
    // ≤ 15 digits always round-trip (DBL_DIG), so rounding to 15 pads with zeros.
    let sig = digits.max(15);
    let p = sig - 1;
    let sci = format!("{v:.p$e}");
    // The exponent after rounding to `sig` digits (9.99…e-1 may become 1e0).
    let exp: i32 = sci.rsplit('e').next().and_then(|e| e.parse().ok()).unwrap_or(0);
    if (-4..15).contains(&exp) {
        let decimals = (sig as i32 - 1 - exp).max(1) as usize;
        format!("{v:.decimals$}")
    } else {
        sci
    }
}

/// A JSON value for a flat object.
pub enum Val {
    Num(f64),
    Int(i64),
    Bool(bool),
    Str(String),
    /// Already-rendered JSON (an array, say).
    Raw(String),
    Null,
}

impl From<f64> for Val {
    fn from(v: f64) -> Self {
        Val::Num(v)
    }
}
impl From<bool> for Val {
    fn from(v: bool) -> Self {
        Val::Bool(v)
    }
}
impl From<u8> for Val {
    fn from(v: u8) -> Self {
        Val::Int(v.into())
    }
}
impl From<u16> for Val {
    fn from(v: u16) -> Self {
        Val::Int(v.into())
    }
}
impl From<u32> for Val {
    fn from(v: u32) -> Self {
        Val::Int(v.into())
    }
}
impl<T: Into<Val>> From<Option<T>> for Val {
    fn from(v: Option<T>) -> Self {
        v.map_or(Val::Null, Into::into)
    }
}

/// A flat JSON object in insertion order.
#[derive(Default)]
pub struct Json(Vec<(&'static str, Val)>);

impl Json {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn set(mut self, key: &'static str, v: impl Into<Val>) -> Self {
        self.0.push((key, v.into()));
        self
    }

    pub fn render(&self) -> String {
        let mut s = String::from("{");
        for (i, (k, v)) in self.0.iter().enumerate() {
            if i > 0 {
                s.push_str(", ");
            }
            let _ = write!(s, "\"{k}\": ");
            match v {
                Val::Num(x) => s.push_str(&num(*x)),
                Val::Int(x) => {
                    let _ = write!(s, "{x}");
                }
                Val::Bool(b) => {
                    let _ = write!(s, "{b}");
                }
                Val::Str(t) => {
                    s.push('"');
                    for c in t.chars() {
                        match c {
                            '"' => s.push_str("\\\""),
                            '\\' => s.push_str("\\\\"),
                            c if (c as u32) < 0x20 => {
                                let _ = write!(s, "\\u{:04x}", c as u32);
                            }
                            c => s.push(c),
                        }
                    }
                    s.push('"');
                }
                Val::Raw(r) => s.push_str(r),
                Val::Null => s.push_str("null"),
            }
        }
        s.push('}');
        s
    }
}

/// A CSV row of numbers.
pub fn csv_row(values: &[f64]) -> String {
    values.iter().map(|v| num(*v)).collect::<Vec<_>>().join(",")
}
