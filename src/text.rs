//! Constant text that lives in flash on the chip.
//!
//! On AVR every `&'static str` literal is copied into SRAM at boot (.rodata is
//! part of .data there), and the app's replies, reasons and names would fill
//! the 3.5 KiB static-RAM budget (`memory.x`) on their own. [`t!`](crate::t) puts a literal in
//! `.progmem.data` instead and gives a [`Text`] handle that reads it with `lpm`
//! one byte at a time. On the host the same handle wraps a plain `&'static str`,
//! so host tests see exactly the bytes the chip sends.

pub mod line;

/// A handle to constant text (flash on AVR, a plain static elsewhere). Copy,
/// 4 bytes on the chip.
#[derive(Clone, Copy)]
pub struct Text {
    #[cfg(target_arch = "avr")]
    ptr: *const u8,
    #[cfg(target_arch = "avr")]
    len: u16,
    #[cfg(not(target_arch = "avr"))]
    s: &'static str,
}

// SAFETY: the bytes behind a Text are immutable statics.
unsafe impl Sync for Text {}
unsafe impl Send for Text {}

impl Text {
    /// Used by [`t!`]; `bytes` must be a `.progmem.data` static on AVR.
    #[doc(hidden)]
    #[cfg(target_arch = "avr")]
    pub const fn from_progmem(bytes: &'static [u8]) -> Text {
        Text { ptr: bytes.as_ptr(), len: bytes.len() as u16 }
    }

    #[doc(hidden)]
    #[cfg(not(target_arch = "avr"))]
    pub const fn from_str(s: &'static str) -> Text {
        Text { s }
    }

    /// Bytes of text.
    #[inline]
    pub fn len(&self) -> usize {
        #[cfg(target_arch = "avr")]
        return self.len as usize;
        #[cfg(not(target_arch = "avr"))]
        return self.s.len();
    }

    /// The first `n` bytes (all of them when `n` is past the end).
    pub fn prefix(self, n: usize) -> Text {
        #[cfg(target_arch = "avr")]
        return Text { ptr: self.ptr, len: (self.len as usize).min(n) as u16 };
        #[cfg(not(target_arch = "avr"))]
        return Text { s: self.s.get(..n).unwrap_or(self.s) };
    }

    /// No bytes.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Byte `i` (0 past the end).
    #[inline]
    pub fn byte(&self, i: usize) -> u8 {
        if i >= self.len() {
            return 0;
        }
        #[cfg(target_arch = "avr")]
        // SAFETY: `i < len`, and `ptr..ptr + len` is the `.progmem.data`
        // static `t!` made.
        return unsafe { flash_byte(self.ptr.wrapping_add(i)) };
        #[cfg(not(target_arch = "avr"))]
        return self.s.as_bytes()[i];
    }

    /// The bytes, read one at a time.
    pub fn bytes(self) -> impl Iterator<Item = u8> {
        (0..self.len()).map(move |i| self.byte(i))
    }

    /// Equal to `other` byte for byte.
    pub fn eq_bytes(&self, other: &[u8]) -> bool {
        other.len() == self.len() && other.iter().enumerate().all(|(i, &b)| self.byte(i) == b)
    }

    /// Equal to `other` byte for byte, ignoring ASCII case (command
    /// keywords: `STOP` is `stop`).
    pub fn eq_ignore_case(&self, other: &[u8]) -> bool {
        other.len() == self.len() && other.iter().enumerate().all(|(i, b)| self.byte(i).eq_ignore_ascii_case(b))
    }

    /// The text as a `str` (host only: on the chip it is not in data space).
    #[cfg(not(target_arch = "avr"))]
    pub fn as_str(&self) -> &'static str {
        self.s
    }
}

impl PartialEq for Text {
    fn eq(&self, other: &Text) -> bool {
        other.len() == self.len() && (0..self.len()).all(|i| self.byte(i) == other.byte(i))
    }
}

impl Eq for Text {}

impl PartialEq<&str> for Text {
    fn eq(&self, other: &&str) -> bool {
        self.eq_bytes(other.as_bytes())
    }
}

impl core::fmt::Debug for Text {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        #[cfg(not(target_arch = "avr"))]
        return core::fmt::Debug::fmt(self.s, f);
        #[cfg(target_arch = "avr")]
        return f.write_str("<flash text>");
    }
}

#[cfg(not(target_arch = "avr"))]
impl core::fmt::Display for Text {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.s)
    }
}

impl ufmt::uDisplay for Text {
    fn fmt<W: ufmt::uWrite + ?Sized>(&self, f: &mut ufmt::Formatter<'_, W>) -> Result<(), W::Error> {
        let mut buf = [0u8; 1];
        for b in self.bytes() {
            buf[0] = b;
            // Only ASCII literals are ever stored.
            f.write_str(core::str::from_utf8(&buf).unwrap_or("?"))?;
        }
        Ok(())
    }
}

/// One byte of program memory, by its flash address. Only `.progmem.data`
/// statics are read this way; avr-gcc's linker script puts `.progmem*` in the
/// low 64 KiB, so the 16-bit Z pointer and `lpm` reach them.
///
/// # Safety
/// `p` must point into a live `'static` array placed in `.progmem.data` (on
/// the host, into any live `'static` array): the host version reads it as
/// data.
#[cfg(target_arch = "avr")]
#[inline]
pub unsafe fn flash_byte(p: *const u8) -> u8 {
    let byte: u8;
    // SAFETY: `lpm` only reads program memory.
    unsafe {
        core::arch::asm!("lpm {0}, Z", out(reg) byte, in("Z") p, options(pure, readonly, nostack, preserves_flags));
    }
    byte
}

/// One byte of a constant (host: a plain read).
///
/// # Safety
/// As on the chip: `p` must point into a live `'static` array.
#[cfg(not(target_arch = "avr"))]
#[inline]
pub unsafe fn flash_byte(p: *const u8) -> u8 {
    // SAFETY: the caller's promise.
    unsafe { p.read() }
}

/// Copies a literal's bytes into an array at compile time.
#[doc(hidden)]
pub const fn to_array<const N: usize>(b: &[u8]) -> [u8; N] {
    let mut a = [0u8; N];
    let mut i = 0;
    while i < N {
        a[i] = b[i];
        i += 1;
    }
    a
}

/// `t!("literal")`: a [`Text`] kept in flash on the chip. Any constant
/// `&'static str` works too, such as `t!(env!("CARGO_PKG_VERSION"))`.
#[macro_export]
macro_rules! t {
    ($s:expr) => {{
        #[cfg(target_arch = "avr")]
        {
            const N: usize = $s.len();
            #[link_section = ".progmem.data"]
            static S: [u8; N] = $crate::text::to_array::<N>($s.as_bytes());
            $crate::text::Text::from_progmem(&S)
        }
        #[cfg(not(target_arch = "avr"))]
        {
            $crate::text::Text::from_str($s)
        }
    }};
}

/// The decimal digits of `v` into `out`, most significant first, without
/// leading zeros (`0` is one digit); returns how many. By subtracting powers
/// of ten (16-bit ones for the usual small values): on the ATmega2560 a
/// 32-bit `/ 10` and `% 10` are library calls of several hundred cycles per
/// digit, this is a few dozen.
pub fn decimal(v: u32, out: &mut [u8; 10]) -> usize {
    let mut d = Digits { out, n: 0 };
    let mut small = match u16::try_from(v) {
        Ok(mut s) => {
            d.put16(&mut s, 10_000);
            s
        }
        Err(_) => {
            let mut rest = v;
            for p in [1_000_000_000, 100_000_000, 10_000_000, 1_000_000, 100_000, 10_000] {
                d.put32(&mut rest, p);
            }
            rest as u16
        }
    };
    for p in [1000, 100, 10] {
        d.put16(&mut small, p);
    }
    d.push(b'0' + small as u8);
    d.n
}

/// Digits written so far.
struct Digits<'a> {
    out: &'a mut [u8; 10],
    n: usize,
}

impl Digits<'_> {
    fn push(&mut self, d: u8) {
        if let Some(slot) = self.out.get_mut(self.n) {
            *slot = d;
        }
        self.n += 1;
    }

    /// The digit of `p` in `rest`, unless it is a leading zero.
    fn put32(&mut self, rest: &mut u32, p: u32) {
        let mut d = b'0';
        while *rest >= p {
            *rest -= p;
            d += 1;
        }
        if d != b'0' || self.n > 0 {
            self.push(d);
        }
    }

    fn put16(&mut self, rest: &mut u16, p: u16) {
        let mut d = b'0';
        while *rest >= p {
            *rest -= p;
            d += 1;
        }
        if d != b'0' || self.n > 0 {
            self.push(d);
        }
    }
}
