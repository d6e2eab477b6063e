//! Code above 128 KiB, called the two ways Rust calls code it does not know
//! statically: through a function pointer and through a trait object.
//!
//! A code pointer is a 16-bit word address; the linker must answer each one
//! that names code past 0x20000 with a `jmp` trampoline in low flash (see
//! `xtask/src/elf/code_pointers.rs`). The two functions below live in
//! `.far_text`, which `.cargo/config.toml` places at 0x20000. The firmware
//! prints each pointer it calls through (the word address it holds) and
//! each result; the simavr test `far_call` checks both against the host and
//! the ELF. Built by `cargo avr` with the other firmwares.
#![no_std]
#![no_main]

use avr_device::atmega2560 as pac;
use core::hint::black_box;
use touch_arm::board::fault::halt;
use touch_arm::board::usart::Usart0;
use ufmt::uwriteln;

/// The function-pointer callee (the test computes the same on the host).
#[inline(never)] // reason: far-call
#[link_section = ".far_text"]
fn far_mix(x: u16) -> u16 {
    x.rotate_left(3) ^ 0x5a5a
}

trait Step {
    fn step(&self, x: u16) -> u16;
}

struct Affine {
    mul: u16,
    add: u16,
}

impl Step for Affine {
    #[inline(never)] // reason: far-call
    #[link_section = ".far_text"]
    fn step(&self, x: u16) -> u16 {
        x.wrapping_mul(self.mul).wrapping_add(self.add)
    }
}

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = pac::Peripherals::take() else { halt() };
    let mut serial = Usart0::new(dp.USART0);
    // black_box keeps both calls indirect: LLVM may not see the callee.
    let f: fn(u16) -> u16 = black_box(far_mix);
    let affine = Affine { mul: 7, add: 3 };
    let d: &dyn Step = black_box(&affine);
    for x in [0x1234u16, 0xbeef] {
        let x = black_box(x);
        let _ = uwriteln!(serial, "fn {} {} {}", f as usize, x, f(x));
        let _ = uwriteln!(serial, "dyn {} {}", x, d.step(x));
    }
    let _ = uwriteln!(serial, "done");
    serial.flush();
    halt()
}
