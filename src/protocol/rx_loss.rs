//! Counting what a full receive buffer drops, in the serial protocol's lines,
//! so every lost line can still be answered (`seam::SerialPort`'s contract).
//! The receiver (USART0's interrupt on the chip, the twin's port on the host)
//! passes every arriving byte through [`LossCounter::byte`], saying whether it
//! kept it; while a loss is open (dropped bytes not yet reported) it must keep
//! nothing, so the loss sits exactly after the last kept byte.

use crate::seam::RxLoss;

/// Receive buffer of USART0, bytes: more than a longest line with its
/// terminator, 11 ms of continuous input at 115200 baud.
pub const RX_BUFFER: usize = 128;
/// Transmit buffer of USART0, bytes: room for the longest reply
/// (`app::text::LINE_CAP`: the `status` with every field of the gripper,
/// the path and lift settings grew past 256) and a telemetry line beside it.
pub const TX_BUFFER: usize = 512;
/// Bytes one 20 ms frame brings or sends at 115200 baud 8N1 (10 bits each).
pub const BYTES_PER_FRAME: usize = 230;

/// The line state of the received stream, across kept and dropped bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LossCounter {
    /// The line in progress has a byte (kept or dropped).
    line_open: bool,
    /// The line in progress lost a byte.
    line_damaged: bool,
    /// ...and was already counted in a loss taken before.
    line_counted: bool,
    /// The last byte was `\r`: a `\n` now completes that terminator.
    after_cr: bool,
    /// Bytes were dropped and not yet taken.
    open: bool,
    loss: RxLoss,
}

impl LossCounter {
    /// A counter at the start of a line, with nothing lost.
    pub const fn new() -> Self {
        LossCounter {
            line_open: false,
            line_damaged: false,
            line_counted: false,
            after_cr: false,
            open: false,
            loss: RxLoss { lines: 0, rest_damaged: false, after_cr: false },
        }
    }

    /// True while dropped bytes wait to be reported: the receiver keeps
    /// nothing until [`LossCounter::take`].
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// One arriving byte, `kept` in the buffer or dropped. Line ends are
    /// `command::LineBuffer`'s: `\r`, `\n`, and `\r\n` as one.
    pub fn byte(&mut self, b: u8, kept: bool) {
        let after_cr = core::mem::replace(&mut self.after_cr, b == b'\r');
        let folded = b == b'\n' && after_cr;
        let ends_line = b == b'\r' || (b == b'\n' && !after_cr);
        if !kept {
            self.open = true;
            self.loss.after_cr = b == b'\r';
        }
        if ends_line {
            if !kept && self.line_open && !self.line_counted {
                self.loss.lines = self.loss.lines.saturating_add(1);
            }
            self.line_open = false;
            self.line_damaged = false;
            self.line_counted = false;
        } else if !folded {
            self.line_open = true;
            self.line_damaged |= !kept;
        }
    }

    /// The loss since the last call, if bytes were dropped; the receiver may
    /// keep bytes again.
    pub fn take(&mut self) -> Option<RxLoss> {
        if !core::mem::replace(&mut self.open, false) {
            return None;
        }
        let rest_damaged = self.line_open && self.line_damaged;
        if rest_damaged && !self.line_counted {
            self.loss.lines = self.loss.lines.saturating_add(1);
            self.line_counted = true;
        }
        self.loss.rest_damaged = rest_damaged;
        Some(core::mem::take(&mut self.loss))
    }
}
