//! The serial protocol: command lines parsed into [`command::Command`]s, and
//! the count of lines a full receive buffer lost ([`rx_loss`]).

pub mod command;
pub mod rx_loss;
