//! The settings a user can change and keep: their values and field vocabulary
//! ([`settings`]) and the EEPROM record that stores them twice with a CRC
//! ([`store`], [`crc`]); the saved poses, stored the same way ([`poses`]).

pub mod crc;
pub mod poses;
pub mod settings;
pub mod store;
