//! xtask: the touch-arm repository's tooling, run as `cargo xtask …` (the
//! alias in `.cargo/config.toml`). The post-link checks on a firmware ELF
//! (`elf`), the benchmark report that scripts/bench.sh writes
//! (`bench_report`), `avr-run` (a firmware under simavr until `done`) and
//! `avr-hex` (the firmware as Intel HEX, `hex`).

#![deny(missing_docs)]

pub mod bench_report;
pub mod cli;
pub mod elf;
pub mod hex;
