//! The screen as the page sees it: the decoded ILI9341 picture, and the
//! rectangle that changed since the last look, sent as a patch.
//!
//! The firmware redraws only what changed, so a patch is usually small (the
//! progress bar, a line of text); a full redraw shows up over a few patches
//! because the bench looks every tick while the firmware is still drawing.

use base64::Engine;

use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use hal_sim::display::Framebuffer;
use touch_arm_rig::lcd_bus::raw565;

/// The changed rectangle of the screen, its pixels row by row as RGB565
/// (the ILI9341's own format, little-endian: the page expands it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Patch {
    pub seq: u64,
    pub x: u32,
    pub y: u32,
    pub w: u32,
    pub h: u32,
    pub rgb565: Vec<u8>,
}

impl Patch {
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "seq": self.seq, "x": self.x, "y": self.y, "w": self.w, "h": self.h,
            "rgb565": base64::engine::general_purpose::STANDARD.encode(&self.rgb565),
        })
    }
}

/// The last picture published and its sequence number.
pub struct ScreenTracker {
    current: Framebuffer,
    seq: u64,
}

impl Default for ScreenTracker {
    fn default() -> Self {
        ScreenTracker::new(320, 240)
    }
}

impl ScreenTracker {
    /// A screen of `width`×`height` in landscape, black as the
    /// controller's power-on GRAM.
    pub fn new(width: u32, height: u32) -> Self {
        ScreenTracker { current: Framebuffer::new(width, height, Rgb565::BLACK), seq: 0 }
    }

    /// Takes `now` as the current picture; the patch covering every changed
    /// pixel, or `None` if nothing changed.
    pub fn update(&mut self, now: Framebuffer) -> Option<Patch> {
        let (w, h) = (self.current.width() as usize, self.current.height() as usize);
        if now.width() as usize != w || now.height() as usize != h {
            return None;
        }
        let (old, new) = (self.current.pixels(), now.pixels());
        let mut bounds: Option<(usize, usize, usize, usize)> = None;
        for y in 0..h {
            let row = y * w;
            let (a, b) = (&old[row..row + w], &new[row..row + w]);
            if a == b {
                continue;
            }
            let x0 = a.iter().zip(b).position(|(p, q)| p != q).unwrap_or(0);
            let x1 = w - 1 - a.iter().zip(b).rev().position(|(p, q)| p != q).unwrap_or(0);
            bounds = Some(match bounds {
                None => (x0, y, x1, y),
                Some((bx0, by0, bx1, _)) => (bx0.min(x0), by0, bx1.max(x1), y),
            });
        }
        let (x0, y0, x1, y1) = bounds?;
        self.current = now;
        self.seq += 1;
        Some(self.patch(x0, y0, x1 - x0 + 1, y1 - y0 + 1))
    }

    /// The whole current picture as one patch (for a page that just connected).
    pub fn keyframe(&self) -> Patch {
        self.patch(0, 0, self.current.width() as usize, self.current.height() as usize)
    }

    /// Bumped each time the picture changed.
    pub fn seq(&self) -> u64 {
        self.seq
    }

    pub fn current(&self) -> &Framebuffer {
        &self.current
    }

    fn patch(&self, x: usize, y: usize, w: usize, h: usize) -> Patch {
        let stride = self.current.width() as usize;
        let px = self.current.pixels();
        let mut rgb565 = Vec::with_capacity(w * h * 2);
        for row in y..y + h {
            for &c in &px[row * stride + x..row * stride + x + w] {
                rgb565.extend_from_slice(&raw565(c).to_le_bytes());
            }
        }
        Patch { seq: self.seq, x: x as u32, y: y as u32, w: w as u32, h: h as u32, rgb565 }
    }
}

/// PNG bytes of a picture.
pub fn png(fb: &Framebuffer) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    fb.write_png(&mut out)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn filled(c: Rgb565) -> Framebuffer {
        Framebuffer::new(320, 240, c)
    }

    #[test]
    fn patches_cover_exactly_the_changed_rectangle() {
        let mut t = ScreenTracker::default();
        assert_eq!(t.update(filled(Rgb565::BLACK)), None);
        let mut fb = filled(Rgb565::BLACK);
        fb.set_pixel(10, 20, Rgb565::RED);
        fb.set_pixel(30, 25, Rgb565::BLUE);
        let p = t.update(fb.clone()).expect("changed");
        assert_eq!((p.seq, p.x, p.y, p.w, p.h), (1, 10, 20, 21, 6));
        assert_eq!(p.rgb565.len(), 21 * 6 * 2);
        assert_eq!(&p.rgb565[..2], &raw565(Rgb565::RED).to_le_bytes());
        let last = p.rgb565.len() - 2;
        assert_eq!(&p.rgb565[last..], &raw565(Rgb565::BLUE).to_le_bytes());
        assert_eq!(t.update(fb), None, "no change, no patch");
        assert_eq!(t.seq(), 1);
        let k = t.keyframe();
        assert_eq!((k.x, k.y, k.w, k.h, k.rgb565.len()), (0, 0, 320, 240, 320 * 240 * 2));
        let png = png(t.current()).unwrap();
        assert_eq!(&png[..4], b"\x89PNG");
    }
}
