//! armsim: the touch-arm method on a PC, in f64, with no hardware and no C
//! compiler (the core crate and plotting only). `cli` is the `armsim`
//! command line (one subcommand per task), `opts` the argument types its
//! subcommands share, `path` and `paper` the larger subcommands; `args`,
//! `report` and `plot` are
//! the command-line conventions, the lossless JSON/CSV numbers and the
//! stacked plots that the main job (`touch-arm-bench`) shares.

#![deny(missing_docs)]

pub mod args;
pub mod cli;
pub mod opts;
pub mod paper;
pub mod path;
pub mod plot;
pub mod report;
