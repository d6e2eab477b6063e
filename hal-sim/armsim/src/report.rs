//! Machine-readable output for `armsim` (and the main job's summary): flat JSON
//! objects and CSV rows. Every number is printed losslessly (it reads back as
//! the same f64) with at least 15 significant digits; a non-finite value is
//! `null` in JSON and an empty cell in CSV.

use std::fmt::Write;

/// Fewest significant digits printed (DBL_DIG: any 15-digit decimal survives
/// a round trip through f64, so the padding never changes the value).
const MIN_DIGITS: usize = 15;

/// A finite `v` as a JSON/CSV number: the shortest decimal that reads back as
/// the same f64 (Rust's `{:e}` Display), padded with zeros to 15 significant
/// digits. The digits are never rounded again: re-rounding the exact binary
/// value to the shortest form's length can land on the other neighbour near
/// a power of two (2⁻²⁴ would print as 5.960464477539062e-8, another double).
/// Fixed notation for magnitudes in [1e-4, 1e15), scientific outside.
fn finite_num(v: f64) -> String {
    debug_assert!(v.is_finite());
    if v == 0.0 {
        return if v.is_sign_negative() { "-0.0".into() } else { "0.0".into() };
    }
    // "-5.960464477539063e-8": sign, one digit, the rest, decimal exponent.
    let shortest = format!("{v:e}");
    let (mantissa, exp) = shortest.split_once('e').unwrap_or((&shortest, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let sign = if v < 0.0 { "-" } else { "" };
    let mut digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    while digits.len() < MIN_DIGITS {
        digits.push('0');
    }
    if !(-4..15).contains(&exp) {
        return format!("{sign}{}.{}e{exp}", &digits[..1], &digits[1..]);
    }
    if exp < 0 {
        let zeros = "0".repeat((-exp - 1) as usize);
        return format!("{sign}0.{zeros}{digits}");
    }
    let (int, frac) = digits.split_at(exp as usize + 1);
    format!("{sign}{int}.{}", if frac.is_empty() { "0" } else { frac })
}

/// `v` as a JSON number ([`finite_num`]), `null` when not finite.
pub fn num(v: f64) -> String {
    if v.is_finite() {
        finite_num(v)
    } else {
        "null".into()
    }
}

/// A JSON value for a flat object.
pub enum Val {
    /// A number, printed losslessly; non-finite is `null`.
    Num(f64),
    /// An integer.
    Int(i64),
    /// `true` or `false`.
    Bool(bool),
    /// A string, escaped.
    Str(String),
    /// Already-rendered JSON (an array, say).
    Raw(String),
    /// `null`.
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
    /// An empty object.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends `key` with value `v` (keys print in the order set).
    pub fn set(mut self, key: &'static str, v: impl Into<Val>) -> Self {
        self.0.push((key, v.into()));
        self
    }

    /// The object as one line of JSON, numbers lossless (see [`num`]).
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

/// A CSV row of numbers; a non-finite value is an empty cell (what
/// spreadsheets, pandas and R read as missing).
pub fn csv_row(values: &[f64]) -> String {
    values.iter().map(|&v| if v.is_finite() { finite_num(v) } else { String::new() }).collect::<Vec<_>>().join(",")
}
