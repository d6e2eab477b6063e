//! The serial protocol: command lines parsed into [`command::Command`]s.

pub mod command;
