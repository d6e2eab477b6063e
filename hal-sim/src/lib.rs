pub use touch_arm;
