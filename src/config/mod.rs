//! The settings a user can change and keep: their values and field vocabulary
//! ([`settings`]) and the EEPROM record that stores them twice with a CRC
//! ([`store`], [`crc`]); the saved poses and the gripper's calibration,
//! stored the same way in their own records ([`poses`], [`grip`]), and the
//! display overrides ([`lcd`]) and the carer's access settings ([`access`]).

pub mod access;
pub mod crc;
pub mod grip;
pub mod lcd;
pub mod poses;
pub mod settings;
pub mod store;
