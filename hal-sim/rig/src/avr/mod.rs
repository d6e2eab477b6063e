//! Runs a real AVR firmware ELF under simavr (through `simavr-ffi`) and gives
//! host tests what they need to judge it: USART0 traffic both ways, cycle-
//! stamped pin edges (servo pulses on PL3/4/5 are measured from the pin, not
//! from register values), port states, ADC input injection, SRAM and ELF
//! symbols, and detection of a firmware that stopped.
//!
//! One [`Avr`] owns one simavr core. simavr calls back into Rust through
//! `extern "C"` functions whose `param` points at a heap block the `Avr`
//! owns (`Shared`); the block is allocated before any callback is
//! registered and freed only after the core is torn down, and the `Avr` is
//! neither `Send` nor `Sync` (it holds raw pointers), so callbacks never
//! race the owner. Callbacks run only inside `avr_run`, i.e. inside the
//! `run_*` methods, which hold `&mut self`.
//!
//! simavr behaviours worth knowing (the harness corrects the first four):
//! - its default sleep handler `usleep`s to keep simulated time in step with
//!   the wall clock, and the UART `usleep`s on every status poll: both are
//!   switched off here, the simulation runs as fast as it can;
//! - OCRnx is not double-buffered in fast PWM (see `ocr_buffer`);
//! - the UART character time ignores U2X/frame changes made after UBRR and
//!   counts 11 bits for 8N1 (see `uart`);
//! - disconnecting a compare output leaves the pin at the waveform level
//!   (see `oc_release`);
//! - TX bytes are reported when written to UDR, not when sent, and UDRE
//!   rises a character time after the write (no 1-byte TX buffer), so a
//!   polling sender adds its loop latency to every byte;
//! - pin-edge stamps can lag by up to 4 cycles (see `pins`);
//! - while a compare output is connected, PORTx reads back the waveform
//!   level and PINx does not follow it;
//! - timers start their first fast-PWM pulse the moment the clock is
//!   selected;
//! - a watchdog reset zeroes simavr's cycle counter and drops every pending
//!   cycle timer: the harness keeps [`Avr::cycles`] monotonic across resets
//!   and re-arms its own timers (see [`Avr::resets`]).

mod adc;
mod eeprom;
mod history;
mod oc_release;
mod ocr_buffer;
mod pins;
mod port_hook;
mod sys;
mod uart;

use std::ffi::{CStr, CString};
use std::fmt;
use std::os::raw::c_void;
use std::path::Path;
use std::sync::Mutex;

use simavr_ffi as ffi;

pub use adc::{raw_to_millivolts, AdcConversion, AdcHandler, AdcInput, AdcMux, AdcRequest, PortsSnapshot};
pub use pins::{Edge, Pin, PortState, Pulse};
pub use port_hook::{BusDevice, PinDrive, PortLevels, PortListener};
pub use uart::RxPacing;

/// simavr's ELF loader and core constructors touch process-wide state
/// (libelf version, the logger): build cores one at a time.
static LOAD_LOCK: Mutex<()> = Mutex::new(());

/// How often `run_until` re-checks its predicate when nothing observable
/// happened (cycles).
const POLL_CYCLES: u64 = 1024;

/// Instructions simavr may run back to back before it returns to the
/// harness (it always stops early for a due timer or a pending interrupt,
/// so timing is unaffected); simavr's own default of 1 halves the speed.
const DEFAULT_BATCH_CYCLES: u64 = 256;

/// `rjmp .-2`: the endless loop avr-libc's `exit` and most panic handlers end in.
const RJMP_SELF: u16 = 0xcfff;

/// MCUSR's data address on the ATmega2560 (I/O 0x34) and its flags.
const MCUSR: usize = 0x54;
const MCUSR_PORF: u8 = 1 << 0;
const MCUSR_EXTRF: u8 = 1 << 1;
/// The first SRAM byte of the ATmega2560 (below: registers and I/O).
const SRAM_START: usize = 0x200;

/// What SRAM holds after [`Avr::power_cycle`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PowerFill {
    /// Every byte 0.
    Zero,
    /// Pseudo-random bytes from the seed (RAM's power-up garbage).
    Noise(u64),
}

/// The data-space offset the AVR toolchain gives SRAM symbols in ELF files.
const DATA_SEGMENT: u32 = 0x0080_0000;

/// Why the firmware is considered stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HaltReason {
    /// `sleep` with interrupts disabled: nothing can ever wake the core.
    SleepWithInterruptsOff,
    /// simavr stopped the core: PC ran past the end of flash.
    Crashed,
    /// An opcode the ATmega does not have (PC stepped over it).
    BadOpcode(u16),
    /// `cli` followed by a jump-to-self: avr-libc's `exit`, or a hang.
    InterruptsOffLoop,
    /// The core loops on a jump-to-self inside the Rust panic machinery
    /// (`rust_begin_unwind`, or `core::panicking::*` where LTO inlined the
    /// handler): a `#[panic_handler]` that ends in `loop {}`, with or without
    /// interrupts. Whatever the handler printed before is in the output.
    Panicked,
}

#[derive(Debug, Clone, PartialEq, Eq)]
/// Where and why the firmware stopped.
pub struct Halt {
    /// Why it stopped.
    pub reason: HaltReason,
    /// Byte address.
    pub pc: u32,
    /// CPU cycle of the stop.
    pub cycle: u64,
    /// The (mangled) ELF symbol containing `pc`, if any.
    pub function: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
/// Why an [`Avr`] call failed.
pub enum Error {
    /// simavr could not read or load the ELF.
    Load(String),
    /// simavr has no core for this MCU name.
    UnknownMcu(String),
    /// The core lacks this peripheral or port.
    Missing(String),
    /// A memory access outside the core's data space (registers, I/O and SRAM).
    OutOfRange {
        /// First address asked for.
        addr: u32,
        /// Bytes asked for.
        len: usize,
    },
    /// The ELF has no symbol of this name.
    NoSymbol(String),
    /// The firmware stopped (crash, `sleep` with interrupts off, a panic).
    Halted(Halt),
    /// `run_until`'s condition did not become true within the budget.
    Timeout {
        /// The cycle budget that ran out.
        cycles: u64,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Load(m) => write!(f, "cannot load firmware: {m}"),
            Error::UnknownMcu(m) => write!(f, "simavr does not know MCU {m:?}"),
            Error::Missing(m) => write!(f, "this core has no {m}"),
            Error::OutOfRange { addr, len } => write!(f, "{len} bytes at {addr:#x} are outside memory"),
            Error::NoSymbol(s) => write!(f, "no symbol {s:?} in the ELF"),
            Error::Halted(h) => {
                write!(f, "firmware stopped ({:?}) at pc {:#x}", h.reason, h.pc)?;
                if let Some(name) = &h.function {
                    write!(f, " in {name}")?;
                }
                write!(f, ", cycle {}", h.cycle)
            }
            Error::Timeout { cycles } => write!(f, "condition not met within {cycles} cycles"),
        }
    }
}

impl std::error::Error for Error {}

/// Core state as seen between instructions.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Status {
    /// Executing instructions.
    Running,
    /// `sleep` with interrupts enabled (waits for an interrupt).
    Sleeping,
    /// Stopped for good: see the [`Halt`].
    Halted(Halt),
}

/// An ELF symbol. `addr` is as the toolchain writes it: flash symbols are
/// byte addresses, SRAM symbols carry the 0x800000 data-segment offset.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Symbol {
    /// The symbol's name as the ELF spells it (mangled for Rust).
    pub name: String,
    /// Its address (see the type's note on the data-segment offset).
    pub addr: u32,
    /// Its size, bytes.
    pub size: u32,
}

impl Symbol {
    /// The SRAM address of a data symbol.
    pub fn data_addr(&self) -> Option<u16> {
        self.addr.checked_sub(DATA_SEGMENT).and_then(|a| u16::try_from(a).ok())
    }
}

/// State the simavr callbacks write into. Allocated once per core, never
/// moved while the core lives.
pub(crate) struct Shared {
    pub(crate) avr: *mut ffi::avr_t,
    /// Bumped on anything a `run_until` predicate could be waiting for.
    pub(crate) events: u64,
    pub(crate) uart: uart::UartState,
    pub(crate) ports: Vec<pins::PortInfo>,
    pub(crate) watches: Vec<*mut pins::PortWatch>,
    pub(crate) port_listeners: Vec<port_hook::Listener>,
    /// Per port index: the notify hook, once some listener wants that port.
    pub(crate) port_hooks: Vec<*mut port_hook::PortHook>,
    pub(crate) adc: adc::AdcState,
    pub(crate) bad_opcode: Option<(u32, u16)>,
    pub(crate) ocr_hooks: Vec<*mut ocr_buffer::OcrHook>,
    pub(crate) com_hooks: Vec<*mut oc_release::ComHook>,
    /// A panic caught in a user callback, re-raised after `avr_run`.
    pub(crate) callback_panic: Option<Box<dyn std::any::Any + Send>>,
    /// simavr's counter restarts at 0 on reset: cycles before the last reset.
    pub(crate) cycle_base: u64,
    pub(crate) resets: u32,
    pub(crate) reset_pending: bool,
    pub(crate) core_reset: Option<unsafe extern "C" fn(*mut ffi::avr_t)>,
}

impl Shared {
    /// Cycles since load, across resets.
    ///
    /// # Safety
    /// `self.avr` must be live.
    pub(crate) unsafe fn now(&self) -> u64 {
        self.cycle_base + (*self.avr).cycle
    }
}

/// A simulated AVR running one firmware image.
pub struct Avr {
    avr: *mut ffi::avr_t,
    shared: *mut Shared,
    symbols: Vec<Symbol>,
    panic_ranges: Vec<(u32, u32)>,
    halt: Option<Halt>,
    paint: Option<StackPaint>,
    batch: u64,
    /// Where the current run must stop (total cycles), re-armed after a reset.
    stop_at: Option<u64>,
}

/// The region [`Avr::paint_stack`] filled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StackPaint {
    /// First painted byte (end of .data/.bss/.noinit).
    pub from: u16,
    /// One past the last painted byte.
    pub to: u16,
    /// The byte written to every painted cell.
    pub pattern: u8,
}

unsafe extern "C" fn sleep_noop(_avr: *mut ffi::avr_t, _how_long: u64) {}

unsafe extern "C" fn stop_timer(_avr: *mut ffi::avr_t, _when: u64, _param: *mut c_void) -> u64 {
    0
}

/// Wraps the core's reset (simavr calls it inside `avr_reset`, after
/// clearing the cycle timers and before zeroing the cycle counter).
unsafe extern "C" fn on_reset(avr: *mut ffi::avr_t) {
    let shared = (*avr).custom.data.cast::<Shared>();
    (*shared).cycle_base += (*avr).cycle;
    // avr_reset zeroes it too, but only after the io modules' resets.
    (*avr).cycle = 0;
    (*shared).resets += 1;
    // The registers were cleared without pin IRQs: record what that did.
    let s = &*shared;
    let now = s.now();
    for &w in &s.watches {
        if let Some(port) = s.ports.get((*w).port) {
            (*w).update(pins::levels(port, avr), now);
        }
    }
    (*shared).reset_pending = true;
    (*shared).events += 1;
    ocr_buffer::forget_pending(&(*shared).ocr_hooks);
    oc_release::forget_latches(&(*shared).com_hooks);
    (*shared).uart.pump_armed = false;
    if let Some(f) = (*shared).core_reset {
        f(avr);
    }
}

unsafe extern "C" fn on_bad_opcode(_irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    let shared = param.cast::<Shared>();
    if (*shared).bad_opcode.is_none() {
        (*shared).bad_opcode = Some(((*(*shared).avr).pc, value as u16));
    }
}

impl Avr {
    /// Loads `elf` into a fresh `mcu` core (simavr name, e.g. "atmega2560")
    /// clocked at `cpu_hz`, with Vcc = AVcc = AREF = 5 V. Nothing runs yet.
    pub fn load(elf: impl AsRef<Path>, mcu: &str, cpu_hz: u32) -> Result<Avr, Error> {
        let path = elf.as_ref();
        let c_path = CString::new(path.to_string_lossy().as_bytes())
            .map_err(|_| Error::Load(format!("{}: NUL in path", path.display())))?;
        let c_mcu = CString::new(mcu).map_err(|_| Error::UnknownMcu(mcu.to_owned()))?;
        if !path.is_file() {
            return Err(Error::Load(format!("{}: no such file", path.display())));
        }

        let _guard = LOAD_LOCK.lock().unwrap_or_else(|e| e.into_inner());
        sys::install_logger();
        // SAFETY: elf_firmware_t is plain C data; simavr requires it zeroed.
        let mut fw: Box<ffi::elf_firmware_t> = Box::new(unsafe { std::mem::zeroed() });
        // SAFETY: valid C string and zeroed firmware struct.
        if unsafe { ffi::elf_read_firmware(c_path.as_ptr(), &mut *fw) } != 0 {
            return Err(Error::Load(format!("{}: not a readable ELF", path.display())));
        }
        let symbols = unsafe { take_symbols(&mut fw) };

        // SAFETY: valid C string; a null result means "unknown".
        let avr = unsafe { ffi::avr_make_mcu_by_name(c_mcu.as_ptr()) };
        if avr.is_null() {
            unsafe { free_chunks(&mut fw) };
            return Err(Error::UnknownMcu(mcu.to_owned()));
        }
        // SAFETY: avr is a freshly made core; init then load is simavr's order.
        unsafe {
            ffi::avr_init(avr);
            fw.frequency = cpu_hz;
            fw.vcc = 5000;
            fw.avcc = 5000;
            fw.aref = 5000;
            ffi::avr_load_firmware(avr, &mut *fw);
            (*avr).frequency = cpu_hz;
            (*avr).sleep = Some(sleep_noop);
            (*avr).run_cycle_limit = DEFAULT_BATCH_CYCLES;
        }

        let shared = Box::into_raw(Box::new(Shared {
            avr,
            events: 0,
            uart: uart::UartState::new(),
            ports: Vec::new(),
            watches: Vec::new(),
            port_listeners: Vec::new(),
            port_hooks: Vec::new(),
            adc: adc::AdcState::new(),
            bad_opcode: None,
            ocr_hooks: Vec::new(),
            com_hooks: Vec::new(),
            callback_panic: None,
            cycle_base: 0,
            resets: 0,
            reset_pending: false,
            core_reset: None,
        }));
        // SAFETY: avr is initialised and shared outlives it (freed in Drop
        // after avr_terminate).
        unsafe {
            (*shared).ports = pins::discover_ports(avr);
            uart::attach(avr, shared, b'0');
            adc::attach(avr, shared);
            (*shared).ocr_hooks = ocr_buffer::install(avr);
            (*shared).com_hooks = oc_release::install(avr);
            let bad = ffi::avr_get_core_irq(avr, ffi::AVR_CORE_BAD_OPCODE as i32);
            ffi::avr_irq_register_notify(bad, Some(on_bad_opcode), shared.cast());
            // `reset` takes no parameter; `custom.data` is free on cores
            // without custom init/deinit hooks (all stock simavr cores).
            let c = &mut (*avr).custom;
            if c.init.is_none() && c.deinit.is_none() && c.data.is_null() {
                c.data = shared.cast();
                (*shared).core_reset = (*avr).reset;
                (*avr).reset = Some(on_reset);
            }
        }

        let panic_ranges = symbols
            .iter()
            .filter(|s| s.addr < DATA_SEGMENT && s.size > 0)
            .filter(|s| s.name.contains("rust_begin_unwind") || s.name.contains("4core9panicking"))
            .map(|s| (s.addr, s.addr + s.size))
            .collect();
        Ok(Avr {
            avr,
            shared,
            symbols,
            panic_ranges,
            halt: None,
            paint: None,
            batch: DEFAULT_BATCH_CYCLES,
            stop_at: None,
        })
    }

    fn shared(&self) -> &Shared {
        // SAFETY: callbacks only run inside run_*, which hold &mut self.
        unsafe { &*self.shared }
    }

    fn shared_mut(&mut self) -> &mut Shared {
        // SAFETY: as in `shared`.
        unsafe { &mut *self.shared }
    }

    // ---- time and execution ------------------------------------------------

    /// The core's clock, Hz (16 MHz on the Mega).
    pub fn frequency(&self) -> u32 {
        unsafe { (*self.avr).frequency }
    }

    /// Cycles simulated since load (monotonic across watchdog resets).
    pub fn cycles(&self) -> u64 {
        unsafe { self.shared().now() }
    }

    /// Resets of the core since load (watchdog, [`Avr::external_reset`],
    /// [`Avr::power_cycle`]).
    pub fn resets(&self) -> u32 {
        self.shared().resets
    }

    /// The RESET pin pulled low and released: simavr's reset (I/O registers
    /// cleared, PC 0, timers stopped) with EXTRF set in MCUSR and SRAM kept,
    /// as on the chip (the reset button, a console opening the port).
    pub fn external_reset(&mut self) {
        self.reset_with_flags(MCUSR_EXTRF);
    }

    /// Power off and on with the same core: SRAM holds `fill` (what RAM
    /// comes up with is undefined on the chip; [`PowerFill`] picks it),
    /// MCUSR says power-on (PORF), and the EEPROM keeps its contents.
    pub fn power_cycle(&mut self, fill: PowerFill) {
        let ram = usize::from(self.ramend()) + 1;
        let bytes: Vec<u8> = match fill {
            PowerFill::Zero => vec![0; ram - SRAM_START],
            PowerFill::Noise(seed) => {
                let mut x = seed | 1;
                (SRAM_START..ram)
                    .map(|_| {
                        // xorshift64
                        x ^= x << 13;
                        x ^= x >> 7;
                        x ^= x << 17;
                        (x >> 24) as u8
                    })
                    .collect()
            }
        };
        let _ = self.write_sram(SRAM_START as u16, &bytes);
        if let Some(m) = self.data_mut().get_mut(MCUSR) {
            *m = 0;
        }
        self.reset_with_flags(MCUSR_PORF);
    }

    /// A reset that keeps SRAM with MCUSR set to exactly `flags` (PORF 1,
    /// EXTRF 2, BORF 4, WDRF 8): a brown-out that RAM survived (BORF), or
    /// what the app sees behind a bootloader that cleared the flags (0).
    pub fn reset_with_mcusr(&mut self, flags: u8) {
        if let Some(m) = self.data_mut().get_mut(MCUSR) {
            *m = 0;
        }
        self.reset_with_flags(flags);
    }

    fn reset_with_flags(&mut self, flags: u8) {
        // avr_reset keeps the MCUSR flags it finds (it clears the other
        // I/O registers), so they are set first.
        if let Some(m) = self.data_mut().get_mut(MCUSR) {
            *m |= flags;
        }
        // A reset revives a core that had stopped (a `sleep` with
        // interrupts off after a panic), as on the chip.
        self.halt = None;
        self.shared_mut().bad_opcode = None;
        // SAFETY: live core, not inside a callback (we hold &mut self).
        unsafe { ffi::avr_reset(self.avr) };
        if let Some(p) = self.shared_mut().callback_panic.take() {
            std::panic::resume_unwind(p);
        }
        if self.shared().reset_pending {
            self.after_reset();
        }
    }

    /// Simulated seconds since load.
    pub fn time_s(&self) -> f64 {
        self.cycles() as f64 / f64::from(self.frequency())
    }

    /// `cycles` at the core's clock, in µs.
    pub fn cycles_to_us(&self, cycles: u64) -> f64 {
        cycles as f64 * 1e6 / f64::from(self.frequency())
    }

    /// The whole cycles nearest `us` µs at the core's clock.
    pub fn us_to_cycles(&self, us: f64) -> u64 {
        (us * f64::from(self.frequency()) / 1e6).round() as u64
    }

    /// Program counter (byte address).
    pub fn pc(&self) -> u32 {
        unsafe { (*self.avr).pc }
    }

    /// Stack pointer.
    pub fn sp(&self) -> u16 {
        let d = self.data();
        u16::from_le_bytes([d[0x5d], d[0x5e]])
    }

    /// The core's state now: running, sleeping or halted.
    pub fn status(&self) -> Status {
        if let Some(h) = &self.halt {
            return Status::Halted(h.clone());
        }
        match self.check_halt() {
            Some(h) => Status::Halted(h),
            None if unsafe { (*self.avr).state } == ffi::cpu_Sleeping as i32 => Status::Sleeping,
            None => Status::Running,
        }
    }

    fn check_halt(&self) -> Option<Halt> {
        // SAFETY: live core; flash has flashend + 1 bytes plus a guard word.
        let (state, pc, irq_on, opcode) = unsafe {
            let a = &*self.avr;
            let pc = a.pc;
            let op = if pc < a.flashend {
                u16::from_le_bytes([*a.flash.add(pc as usize), *a.flash.add(pc as usize + 1)])
            } else {
                0
            };
            (a.state, pc, a.sreg[ffi::S_I as usize] != 0, op)
        };
        let reason = if state == ffi::cpu_Done as i32 {
            Some(HaltReason::SleepWithInterruptsOff)
        } else if state == ffi::cpu_Crashed as i32 {
            Some(HaltReason::Crashed)
        } else if let Some((_, op)) = self.shared().bad_opcode {
            Some(HaltReason::BadOpcode(op))
        } else if opcode == RJMP_SELF && self.panic_ranges.iter().any(|&(lo, hi)| (lo..hi).contains(&pc)) {
            Some(HaltReason::Panicked)
        } else if !irq_on && opcode == RJMP_SELF {
            Some(HaltReason::InterruptsOffLoop)
        } else {
            None
        }?;
        let pc = match reason {
            HaltReason::BadOpcode(_) => self.shared().bad_opcode.map_or(pc, |(p, _)| p),
            _ => pc,
        };
        Some(Halt { reason, pc, cycle: self.cycles(), function: self.function_at(pc).map(|s| s.name.clone()) })
    }

    /// One simavr scheduling step (instructions up to the batch limit or the
    /// next timer event, or a sleep up to that event), then the halt checks.
    fn step(&mut self) -> Result<(), Error> {
        if let Some(h) = &self.halt {
            return Err(Error::Halted(h.clone()));
        }
        // SAFETY: live core; callbacks see `shared` only during this call.
        unsafe { ffi::avr_run(self.avr) };
        if let Some(p) = self.shared_mut().callback_panic.take() {
            std::panic::resume_unwind(p);
        }
        if self.shared().reset_pending {
            self.after_reset();
        }
        if let Some(h) = self.check_halt() {
            self.halt = Some(h.clone());
            return Err(Error::Halted(h));
        }
        Ok(())
    }

    /// Makes sure simavr's scheduler wakes at `cycle` so a run can end there
    /// even while the core sleeps.
    fn arm_stop(&mut self, cycle: u64) {
        self.stop_at = Some(cycle);
        let now = self.cycles();
        if cycle > now {
            unsafe { ffi::avr_cycle_timer_register(self.avr, cycle - now, Some(stop_timer), self.shared.cast()) };
        }
    }

    /// simavr's reset cleared the cycle timers and the batch limit.
    fn after_reset(&mut self) {
        self.shared_mut().reset_pending = false;
        unsafe { (*self.avr).run_cycle_limit = self.batch };
        if let Some(at) = self.stop_at {
            self.arm_stop(at);
        }
        unsafe { uart::arm_pump(self.avr, self.shared) };
    }

    /// How many cycles simavr may run between returns to the harness
    /// (default 256; 1 is simavr's stock behaviour). Timer events and
    /// interrupts still cut a batch short; only halt detection and the
    /// `run_until` polling happen at batch ends.
    pub fn set_batch_cycles(&mut self, cycles: u64) {
        self.batch = cycles.max(1);
        unsafe { (*self.avr).run_cycle_limit = self.batch };
    }

    /// Runs `n` more cycles (may overshoot by part of the last instruction).
    pub fn run_cycles(&mut self, n: u64) -> Result<(), Error> {
        let target = self.cycles().saturating_add(n);
        self.arm_stop(target);
        while self.cycles() < target {
            self.step()?;
        }
        Ok(())
    }

    /// Runs for `seconds` of simulated time.
    pub fn run_for(&mut self, seconds: f64) -> Result<(), Error> {
        let n = (seconds * f64::from(self.frequency())).round() as u64;
        self.run_cycles(n)
    }

    /// Runs until `cond` holds, at most `max_cycles`; returns the cycles
    /// run. `cond` is checked at the start, after every UART byte, watched
    /// pin edge, RX overrun or ADC conversion, and otherwise every 1024
    /// cycles (so use `run_cycles` for pure time conditions).
    pub fn run_until(&mut self, mut cond: impl FnMut(&Avr) -> bool, max_cycles: u64) -> Result<u64, Error> {
        let start = self.cycles();
        let deadline = start.saturating_add(max_cycles);
        self.arm_stop(deadline);
        let mut seen = self.shared().events;
        let mut next_poll = start + POLL_CYCLES;
        if cond(self) {
            return Ok(0);
        }
        loop {
            if self.cycles() >= deadline {
                return Err(Error::Timeout { cycles: max_cycles });
            }
            self.step()?;
            let events = self.shared().events;
            let now = self.cycles();
            if events != seen || now >= next_poll {
                seen = events;
                next_poll = now + POLL_CYCLES;
                if cond(self) {
                    return Ok(now - start);
                }
            }
        }
    }

    /// Runs until USART0 has sent `needle` (anywhere in its output).
    pub fn run_until_output(&mut self, needle: &[u8], max_cycles: u64) -> Result<u64, Error> {
        self.run_until(|a| contains(a.uart_output(), needle), max_cycles)
    }

    // ---- USART0 ------------------------------------------------------------

    /// Every byte the firmware sent on USART0 since load.
    pub fn uart_output(&self) -> &[u8] {
        &self.shared().uart.tx
    }

    /// Cycle at which each byte of [`Avr::uart_output`] was written to UDR0.
    pub fn uart_output_cycles(&self) -> &[u64] {
        &self.shared().uart.tx_cycles
    }

    /// Everything the firmware sent on USART0 so far, as text (invalid UTF-8 replaced).
    pub fn uart_output_string(&self) -> String {
        String::from_utf8_lossy(self.uart_output()).into_owned()
    }

    /// Complete output lines not returned before (`\n` ends a line, a `\r`
    /// before it is dropped); an unfinished line waits for the next call.
    pub fn take_lines(&mut self) -> Vec<String> {
        self.shared_mut().uart.take_lines()
    }

    /// Queues bytes for USART0's receiver; they arrive one character time
    /// apart, once the firmware has enabled RX (see [`RxPacing`]).
    pub fn uart_send(&mut self, bytes: &[u8]) {
        let shared = self.shared;
        self.shared_mut().uart.rx_queue.extend(bytes.iter().copied());
        // SAFETY: live core, not inside a callback.
        unsafe { uart::arm_pump(self.avr, shared) };
    }

    /// How bytes queued for USART0 are delivered to the firmware (see [`RxPacing`]).
    pub fn set_uart_rx_pacing(&mut self, pacing: RxPacing) {
        self.shared_mut().uart.pacing = pacing;
    }

    /// Bytes queued by `uart_send` not yet handed to the receiver.
    pub fn uart_rx_pending(&self) -> usize {
        self.shared().uart.rx_queue.len()
    }

    /// Bytes lost to receiver overrun (only with [`RxPacing::LineRate`]).
    pub fn uart_overruns(&self) -> u64 {
        self.shared().uart.overruns
    }

    // ---- GPIO --------------------------------------------------------------

    fn port_index(&self, port: char) -> Result<usize, Error> {
        self.shared().ports.iter().position(|p| p.name == port).ok_or_else(|| Error::Missing(format!("port {port}")))
    }

    /// The registers of `port` ('A'..'L') now; `Error::Missing` if the core has no such port.
    pub fn port_state(&self, port: char) -> Result<PortState, Error> {
        let i = self.port_index(port)?;
        Ok(unsafe { self.shared().ports[i].state(self.avr) })
    }

    /// Every port's registers.
    pub fn ports(&self) -> PortsSnapshot {
        PortsSnapshot { ports: self.shared().ports.iter().map(|p| unsafe { p.state(self.avr) }).collect() }
    }

    /// The logic level of `pin` now (its PINx bit).
    pub fn pin_level(&self, pin: Pin) -> Result<bool, Error> {
        Ok(self.port_state(pin.port)?.level(pin.bit))
    }

    /// Starts recording `pin`'s edges (from now on).
    pub fn watch_pin(&mut self, pin: Pin) -> Result<(), Error> {
        let port = self.port_index(pin.port)?;
        if pin.bit > 7 {
            return Err(Error::Missing(format!("pin {}{}", pin.port, pin.bit)));
        }
        let avr = self.avr;
        let shared = self.shared;
        let level = unsafe { pins::levels(&self.shared().ports[port], avr) };
        let existing = self.shared().watches.iter().copied().find(|&w| unsafe { (*w).port } == port);
        let watch = match existing {
            Some(w) => w,
            None => {
                let w = Box::into_raw(Box::new(pins::PortWatch {
                    shared,
                    port,
                    mask: 0,
                    last: 0,
                    edges: Default::default(),
                }));
                let irq = self.shared().ports[port].irq;
                unsafe {
                    ffi::avr_irq_register_notify(
                        irq.add(ffi::IOPORT_IRQ_PIN_ALL as usize),
                        Some(pins::on_pin_all),
                        w.cast(),
                    )
                };
                self.shared_mut().watches.push(w);
                w
            }
        };
        // SAFETY: the watch is owned by `shared` and not in use by simavr now.
        let w = unsafe { &mut *watch };
        let m = 1u8 << pin.bit;
        w.mask |= m;
        w.last = (w.last & !m) | (level & m);
        Ok(())
    }

    fn watch_of(&self, pin: Pin) -> Option<&pins::PortWatch> {
        let port = self.port_index(pin.port).ok()?;
        let w = self.shared().watches.iter().copied().find(|&w| unsafe { (*w).port } == port)?;
        let w = unsafe { &*w };
        (w.mask >> pin.bit & 1 == 1).then_some(w)
    }

    /// Recorded edges of a watched pin (empty if not watched).
    pub fn edges(&self, pin: Pin) -> &[Edge] {
        self.watch_of(pin).map_or(&[], |w| &w.edges[usize::from(pin.bit & 7)])
    }

    /// Complete high pulses of a watched pin.
    pub fn pulses(&self, pin: Pin) -> Vec<Pulse> {
        pins::pulses_from(self.edges(pin))
    }

    /// Forgets the edges recorded so far for every watched pin.
    pub fn clear_edges(&mut self) {
        for &w in &self.shared().watches {
            unsafe { (*w).edges.iter_mut().for_each(Vec::clear) };
        }
    }

    /// Calls `f(port, cycle, levels)` after every PORT or DDR write to any
    /// of `ports` (including `sbi`/`cbi` and PINx toggles), with the levels
    /// of all ports at that moment. `f` runs inside simavr; a panic in it is
    /// re-raised from the `run_*` call. Listeners stay for the core's life.
    pub fn add_port_listener(
        &mut self,
        ports: &[char],
        mut f: impl FnMut(char, u64, &PortLevels) + 'static,
    ) -> Result<(), Error> {
        self.add_bus_device(ports, move |port, cycle, levels, _| f(port, cycle, levels))
    }

    /// [`Avr::add_port_listener`] for a device that also answers on the
    /// wire: `f` may drive input pins through its [`PinDrive`] (a display
    /// controller putting a byte on the data lines while RD is low); the
    /// firmware's next instruction reads them.
    pub fn add_bus_device(
        &mut self,
        ports: &[char],
        f: impl FnMut(char, u64, &PortLevels, &mut PinDrive<'_>) + 'static,
    ) -> Result<(), Error> {
        let mut mask = 0u32;
        for &p in ports {
            mask |= 1 << self.port_index(p)?;
        }
        let shared = self.shared;
        for i in 0..self.shared().ports.len() {
            if mask >> i & 1 == 0 || self.shared().port_hooks.iter().any(|&h| unsafe { (*h).port } == i) {
                continue;
            }
            let hook = Box::into_raw(Box::new(port_hook::PortHook { shared, port: i }));
            let irq = self.shared().ports[i].irq;
            // SAFETY: live core; the hook lives until Drop, after avr_terminate.
            unsafe {
                ffi::avr_irq_register_notify(
                    irq.add(ffi::IOPORT_IRQ_PIN_ALL as usize),
                    Some(port_hook::on_port_write),
                    hook.cast(),
                )
            };
            self.shared_mut().port_hooks.push(hook);
        }
        self.shared_mut().port_listeners.push(port_hook::Listener { mask, f: Box::new(f) });
        Ok(())
    }

    /// Drives `pin` from outside (like a switch or a sensor). On an input
    /// this sets PINx (and fires pin-change interrupts); on an output simavr
    /// keeps the firmware's level.
    pub fn drive_pin(&mut self, pin: Pin, high: bool) -> Result<(), Error> {
        let port = self.port_index(pin.port)?;
        if pin.bit > 7 {
            return Err(Error::Missing(format!("pin {}{}", pin.port, pin.bit)));
        }
        let irq = self.shared().ports[port].irq;
        unsafe { ffi::avr_raise_irq(irq.add(usize::from(pin.bit)), u32::from(high)) };
        // simavr raises PIN_ALL only for PORT/DDR writes: record input edges here.
        let now = self.cycles();
        let level = unsafe { pins::levels(&self.shared().ports[port], self.avr) };
        if let Some(&w) = self.shared().watches.iter().find(|&&w| unsafe { (*w).port } == port) {
            if unsafe { (*w).update(level, now) } {
                self.shared_mut().events += 1;
            }
        }
        Ok(())
    }

    // ---- ADC ---------------------------------------------------------------

    /// Fixed input for ADC channel 0..=15 (used when no handler is set).
    pub fn set_adc(&mut self, channel: u8, input: AdcInput) -> Result<(), Error> {
        let slot = self
            .shared_mut()
            .adc
            .inputs
            .get_mut(usize::from(channel))
            .ok_or_else(|| Error::Missing(format!("ADC channel {channel}")))?;
        *slot = input;
        Ok(())
    }

    /// Computes every sampled input on the fly (replaces the fixed inputs).
    /// The handler runs inside simavr; a panic in it is re-raised from the
    /// `run_*` call that triggered the conversion.
    pub fn set_adc_handler(&mut self, handler: impl FnMut(&AdcRequest<'_>) -> AdcInput + 'static) {
        self.shared_mut().adc.handler = Some(Box::new(handler));
    }

    /// Removes the ADC handler: inputs read as simavr's default from now on.
    pub fn clear_adc_handler(&mut self) {
        self.shared_mut().adc.handler = None;
    }

    /// Every conversion the firmware made, in order.
    pub fn adc_conversions(&self) -> &[AdcConversion] {
        &self.shared().adc.log
    }

    /// Supply and reference voltages (simavr's `vcc`, `avcc`, `aref`).
    pub fn set_analog_supplies(&mut self, vcc_mv: u32, avcc_mv: u32, aref_mv: u32) {
        unsafe {
            (*self.avr).vcc = vcc_mv;
            (*self.avr).avcc = avcc_mv;
            (*self.avr).aref = aref_mv;
        }
    }

    // ---- memory and symbols ------------------------------------------------

    fn data_mut(&mut self) -> &mut [u8] {
        // SAFETY: as in `data`; &mut self keeps simavr's callbacks out.
        unsafe { std::slice::from_raw_parts_mut((*self.avr).data, usize::from((*self.avr).ramend) + 1) }
    }

    fn data(&self) -> &[u8] {
        // SAFETY: simavr allocates ramend + 1 bytes of data space at init and
        // never reallocates it.
        unsafe { std::slice::from_raw_parts((*self.avr).data, usize::from((*self.avr).ramend) + 1) }
    }

    /// Last data-space address (RAMEND).
    pub fn ramend(&self) -> u16 {
        unsafe { (*self.avr).ramend }
    }

    /// `len` bytes of data space (registers, I/O, SRAM) from `addr`, read
    /// without I/O side effects.
    pub fn read_sram(&self, addr: u16, len: usize) -> Result<&[u8], Error> {
        let start = usize::from(addr);
        self.data().get(start..start + len).ok_or(Error::OutOfRange { addr: u32::from(addr), len })
    }

    /// Writes data space directly (no I/O side effects).
    pub fn write_sram(&mut self, addr: u16, bytes: &[u8]) -> Result<(), Error> {
        let start = usize::from(addr);
        let end = start + bytes.len();
        if end > usize::from(self.ramend()) + 1 {
            return Err(Error::OutOfRange { addr: u32::from(addr), len: bytes.len() });
        }
        // SAFETY: bounds checked against the data allocation above.
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), (*self.avr).data.add(start), bytes.len()) };
        Ok(())
    }

    /// Writes an I/O register the way the CPU would (`sts`): simavr's
    /// peripheral callbacks run, unlike [`Avr::write_sram`]. Lets a test
    /// disturb the hardware under the firmware (e.g. stop a timer).
    pub fn write_io(&mut self, addr: u16, value: u8) -> Result<(), Error> {
        if !(0x20..=0x1FF).contains(&addr) {
            return Err(Error::OutOfRange { addr: u32::from(addr), len: 1 });
        }
        let slot = usize::from(addr - 0x20);
        // SAFETY: the core is alive (owned by self); slot < 0x1E0 ≤ the io
        // table's 280 entries; the callback is simavr's own for this address.
        unsafe {
            let io = &(*self.avr).io[slot];
            match io.w.c {
                Some(write) => write(self.avr, addr, value, io.w.param),
                None => *(*self.avr).data.add(usize::from(addr)) = value,
            }
        }
        Ok(())
    }

    /// Every symbol of the loaded ELF.
    pub fn symbols(&self) -> &[Symbol] {
        &self.symbols
    }

    /// The symbol named `name`, if the ELF has one.
    pub fn symbol(&self, name: &str) -> Option<&Symbol> {
        self.symbols.iter().find(|s| s.name == name)
    }

    /// Reads a data symbol's bytes (its full ELF size).
    pub fn read_symbol(&self, name: &str) -> Result<&[u8], Error> {
        let s = self.symbol(name).ok_or_else(|| Error::NoSymbol(name.to_owned()))?;
        let addr = s.data_addr().ok_or_else(|| Error::NoSymbol(format!("{name} (not in SRAM)")))?;
        self.read_sram(addr, s.size as usize)
    }

    /// The sized flash symbol containing byte address `pc`.
    pub fn function_at(&self, pc: u32) -> Option<&Symbol> {
        self.symbols
            .iter()
            .filter(|s| s.addr < DATA_SEGMENT && s.size > 0)
            .find(|s| (s.addr..s.addr + s.size).contains(&pc))
    }

    /// Fills the free SRAM between the end of the static data (`__heap_start`,
    /// else `_end`) and the current stack pointer with `pattern`, so
    /// [`Avr::stack_high_water`] can later tell how deep the stack went.
    /// Call it right after `load`.
    pub fn paint_stack(&mut self, pattern: u8) -> Result<StackPaint, Error> {
        let from = ["__heap_start", "_end", "__bss_end"]
            .iter()
            .find_map(|n| self.symbol(n).and_then(Symbol::data_addr))
            .ok_or_else(|| Error::NoSymbol("__heap_start".to_owned()))?;
        let to = self.sp();
        if to <= from {
            return Err(Error::OutOfRange { addr: u32::from(from), len: 0 });
        }
        let fill = vec![pattern; usize::from(to - from)];
        self.write_sram(from, &fill)?;
        let paint = StackPaint { from, to, pattern };
        self.paint = Some(paint);
        Ok(paint)
    }

    /// Deepest stack use since `paint_stack`, in bytes below RAMEND (the
    /// lowest painted byte that changed marks it), and the untouched margin
    /// left above the static data. `None` without a paint.
    pub fn stack_high_water(&self) -> Option<(usize, usize)> {
        let p = self.paint?;
        let region = self.read_sram(p.from, usize::from(p.to - p.from)).ok()?;
        let untouched = region.iter().take_while(|&&b| b == p.pattern).count();
        let lowest = usize::from(p.from) + untouched;
        Some((usize::from(self.ramend()) + 1 - lowest, untouched))
    }
}

impl Drop for Avr {
    fn drop(&mut self) {
        // SAFETY: tear down the core first so no callback can run, then free
        // what the callbacks pointed at.
        unsafe {
            ffi::avr_terminate(self.avr);
            sys::c_free(self.avr);
            let shared = Box::from_raw(self.shared);
            for &w in &shared.watches {
                drop(Box::from_raw(w));
            }
            for &h in &shared.port_hooks {
                drop(Box::from_raw(h));
            }
            for &h in &shared.ocr_hooks {
                drop(Box::from_raw(h));
            }
            for &h in &shared.uart.reg_hooks {
                drop(Box::from_raw(h));
            }
            for &h in &shared.com_hooks {
                drop(Box::from_raw(h));
            }
        }
    }
}

fn contains(hay: &[u8], needle: &[u8]) -> bool {
    needle.is_empty() || hay.windows(needle.len()).any(|w| w == needle)
}

/// Copies simavr's symbol table out of `fw` and frees it (simavr never does).
///
/// # Safety
/// `fw` must have been filled by `elf_read_firmware`.
unsafe fn take_symbols(fw: &mut ffi::elf_firmware_t) -> Vec<Symbol> {
    let mut out = Vec::with_capacity(fw.symbolcount as usize);
    if !fw.symbol.is_null() {
        for i in 0..fw.symbolcount as usize {
            let s = *fw.symbol.add(i);
            if s.is_null() {
                continue;
            }
            let name = CStr::from_ptr((*s).symbol.as_ptr()).to_string_lossy().into_owned();
            out.push(Symbol { name, addr: (*s).addr, size: (*s).size });
            sys::c_free(s);
        }
        sys::c_free(fw.symbol);
    }
    fw.symbol = std::ptr::null_mut();
    fw.symbolcount = 0;
    sys::c_free(fw.file_name);
    fw.file_name = std::ptr::null_mut();
    out
}

/// Frees the loadable chunks of a firmware that will not be loaded.
///
/// # Safety
/// `fw` must have been filled by `elf_read_firmware` and not loaded.
unsafe fn free_chunks(fw: &mut ffi::elf_firmware_t) {
    let mut c = fw.chunks;
    while !c.is_null() {
        let next = (*c).next;
        sys::c_free(c);
        c = next;
    }
    fw.chunks = std::ptr::null_mut();
    sys::c_free(fw.dwarf_file);
    fw.dwarf_file = std::ptr::null_mut();
}
