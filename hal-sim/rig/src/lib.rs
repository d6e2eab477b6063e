//! touch-arm-rig: the real firmware ELF under simavr. The harness (`avr`:
//! USART, pin edges, ports, ADC injection, SRAM), the LCD bus decoders
//! (`lcd_bus`), the twin's touch panel wired to the chip's pins (`panel`)
//! and the firmware session the tests and the main job drive (`firmware`).
//! Builds simavr from C: the crates that need no chip (the twin `hal-sim`,
//! `armsim`) do not depend on this one.

#![deny(missing_docs)]

pub mod avr;
pub mod firmware;
pub mod lcd_bus;
pub mod panel;
