//! Bringing the display up: hardware reset, the ID probe (which controller
//! is on the shield, `ui::controller`), and each controller's initialisation
//! as a script in flash.
//!
//! Scripts are entries of `code, n | WAIT, n parameter bytes[, ms]`: a DCS
//! command and its parameters, or an ILI9325 register index and its 16-bit
//! value (n = 2, upper byte first); `WAIT` adds a delay in milliseconds.
//! Where the values come from:
//!
//! - DCS (ILI9341, ST7789V, ILI9486, ST7796S): SWRESET, 5 ms, SLPOUT, 120 ms (each
//!   datasheet's "Software Reset (01h)" and "Sleep Out (11h)": wait 5 ms
//!   before the next command, 120 ms after sleep out), COLMOD 55h (16 bits
//!   per pixel on the MCU interface, "Pixel Format Set / Interface Pixel
//!   Format (3Ah)"), then MADCTL and DISPON. Everything else stays at the
//!   power-on defaults the datasheets list (no panel-specific gamma or VCOM).
//! - ILI9325: the ILI9325 datasheet's power supply setting flow and display
//!   ON sequence with ILITEK's reference values (driver output SS, line
//!   inversion, BGR entry mode, porches; power control 1–4 with 200 ms for
//!   the capacitors to discharge and 50 ms steps while the supplies come up;
//!   VCOMH, frame rate; 320 gate lines with GS; R07h = 0133h displays the
//!   GRAM). Gamma and partial-display registers stay at their defaults.

use super::{cmd, delay_ms, reg, Bus8, Controller, IdReads, Lcd, Protocol, Rotation};

/// Entry flag: a delay byte (ms) follows the parameters.
const WAIT: u8 = 0x80;

/// The DCS controllers' initialisation (before MADCTL and DISPON).
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static DCS_INIT: [u8; 9] = [cmd::SWRESET, WAIT, 5, cmd::SLPOUT, WAIT, 120, cmd::COLMOD, 1, 0x55];

/// The ILI9325's initialisation (before the entry mode and display on).
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static ILI9325_INIT: [u8; 68] = [
    reg::DRIVER_OUTPUT,
    2,
    0x01,
    0x00, // SS: S720 → S1
    reg::DRIVING_WAVE,
    2,
    0x07,
    0x00, // line inversion
    reg::PORCH,
    2,
    0x02,
    0x07, // back porch 2, front porch 7 lines
    reg::POWER1,
    2,
    0x00,
    0x00, // supplies off
    reg::POWER2,
    2,
    0x00,
    0x07,
    reg::POWER3,
    2,
    0x00,
    0x00,
    reg::POWER4,
    2,
    0x00,
    0x00,
    reg::DISPLAY_CONTROL,
    2 | WAIT,
    0x00,
    0x01,
    200, // discharge
    reg::POWER1,
    2,
    0x16,
    0x90, // SAP, BT, AP
    reg::POWER2,
    2 | WAIT,
    0x02,
    0x27,
    50, // DC1, DC0, VC
    reg::POWER3,
    2 | WAIT,
    0x00,
    0x0D,
    50, // VREG1OUT
    reg::POWER4,
    2,
    0x12,
    0x00, // VCOM amplitude
    reg::POWER7,
    2,
    0x00,
    0x0A, // VCOMH
    reg::FRAME_RATE,
    2 | WAIT,
    0x00,
    0x0D,
    50,
    reg::GATE_SCAN,
    2,
    0xA7,
    0x00, // GS, 320 lines
    reg::BASE_IMAGE,
    2,
    0x00,
    0x01, // REV
];

/// Byte `i` of a script in flash.
fn script_byte(script: &'static [u8], i: usize) -> u8 {
    match script.get(i) {
        // SAFETY: `p` points into one of the `.progmem.data` statics above.
        Some(p) => unsafe { crate::text::flash_byte(p) },
        None => 0,
    }
}

impl<B: Bus8> Lcd<B> {
    /// Resets the controller, reads its ID, drives it with the matching
    /// driver (an ILI9341 when nothing matched) and initialises it in
    /// `rotation`. Returns what the probe read and the controller found.
    pub fn start(&mut self, rotation: Rotation) -> (IdReads, Option<Controller>) {
        self.start_forced(None, rotation, false)
    }

    /// [`Lcd::start`] with the display overrides (`config::lcd`): a
    /// `forced` controller is driven whatever the probe found (the probe
    /// still runs, so the caller can say whether the shield answered as
    /// that controller), `invert` sends the controller's inversion command.
    pub fn start_forced(
        &mut self,
        forced: Option<Controller>,
        rotation: Rotation,
        invert: bool,
    ) -> (IdReads, Option<Controller>) {
        self.hardware_reset();
        let ids = self.probe();
        let found = ids.identify();
        self.controller = forced.or(found).unwrap_or(Controller::Ili9341);
        self.configure(rotation, invert);
        (ids, found)
    }

    /// RST low 1 ms, then 120 ms for the controller to come out of reset
    /// (the longest "reset cancel" time of the datasheets), then the chip
    /// is selected.
    pub(super) fn hardware_reset(&mut self) {
        self.bus.select(false);
        self.bus.set_reset(true);
        delay_ms(1);
        self.bus.set_reset(false);
        delay_ms(1);
        self.bus.set_reset(true);
        delay_ms(120);
        self.bus.select(true);
        self.columns = None;
        self.pages = None;
    }

    /// The three ID reads of `ui::controller`, on a controller just out of
    /// reset.
    pub fn probe(&mut self) -> IdReads {
        let mut ids = IdReads::default();
        self.read_reg(reg::DRIVER_CODE, &mut ids.reg00);
        self.read_reg(cmd::RDID4, &mut ids.id4);
        self.read_reg(cmd::RDDID, &mut ids.rddid);
        ids
    }

    /// `code` as a 16-bit index (a NOP first on the DCS controllers), then
    /// `out.len()` bytes read.
    fn read_reg(&mut self, code: u8, out: &mut [u8]) {
        self.bus.command(0x00);
        self.bus.command(code);
        self.bus.read(out);
    }

    /// Writes ILI9325 register `r` (index, then the value upper byte first).
    pub(super) fn write_reg(&mut self, r: u8, value: u16) {
        self.bus.command(0x00);
        self.bus.command(r);
        self.bus.data(&value.to_be_bytes());
    }

    /// The controller's script, `rotation`, the inversion if asked, display
    /// on. Inverted is the opposite of what the script leaves: INVON on the
    /// DCS controllers (INVOFF is their reset state), R61h's REV cleared on
    /// the ILI9325 (its script sets REV, as the shields' reference code does
    /// for their normally-black panels), as MCUFRIEND_kbv's `invertDisplay`.
    pub(super) fn configure(&mut self, rotation: Rotation, invert: bool) {
        match self.controller.protocol() {
            Protocol::Dcs => {
                self.run_script(&DCS_INIT);
                self.set_rotation(rotation);
                if invert {
                    self.bus.command(cmd::INVON);
                }
                self.bus.command(cmd::DISPON);
            }
            Protocol::Indexed => {
                self.run_script(&ILI9325_INIT);
                self.set_rotation(rotation);
                if invert {
                    self.write_reg(reg::BASE_IMAGE, 0x0000);
                }
                self.write_reg(reg::DISPLAY_CONTROL, 0x0133);
            }
        }
    }

    fn run_script(&mut self, script: &'static [u8]) {
        let indexed = self.controller.protocol() == Protocol::Indexed;
        let mut i = 0;
        while i < script.len() {
            let code = script_byte(script, i);
            let n = script_byte(script, i + 1);
            if indexed {
                self.bus.command(0x00);
            }
            self.bus.command(code);
            i += 2;
            for _ in 0..n & !WAIT {
                self.bus.data(&[script_byte(script, i)]);
                i += 1;
            }
            if n & WAIT != 0 {
                delay_ms(u16::from(script_byte(script, i)));
                i += 1;
            }
        }
    }
}
