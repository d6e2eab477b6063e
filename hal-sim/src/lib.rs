pub use touch_arm;

#[cfg(feature = "simavr")]
pub mod avr;
