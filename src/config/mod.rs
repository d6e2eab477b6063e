//! The settings a user can change and keep: their values and field vocabulary
//! ([`settings`]) and the EEPROM record that stores them twice with a CRC
//! ([`store`], [`crc`]).

pub mod crc;
pub mod settings;
pub mod store;
