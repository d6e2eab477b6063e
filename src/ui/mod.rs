//! The touch screen's user interface, pure and `no_std`: it draws on any
//! embedded-graphics `DrawTarget<Color = Rgb565>` of 320×240 or 480×320
//! (laid out by [`layout::Layout`]) that also
//! implements the one-method [`draw::Canvas`] (an empty `impl` will do; the
//! ILI9341 driver overrides it to stream colour runs fast), and maps touches
//! back to buttons and workspace points.
//!
//! - [`layout`]: the screen layout for both panel sizes, from one description,
//!   and the panel ↔ pixel ↔ workspace mappings (read its module docs for why
//!   the map is a sub-rectangle with a guard band around it).
//! - [`screen`]: [`Ui`], which draws a [`UiModel`] and afterwards repaints only
//!   what changed, and hit-tests touches ([`Hit`]).
//! - [`calibration`]: the crosshair calibration flow ([`CalibrationFlow`]).
//! - [`font`]: the UI's own 5×8 bitmap font (in flash on the chip);
//!   [`draw`]: rectangles and text on top of `fill_solid`/`fill_contiguous`.

pub mod calibration;
pub mod controller;
pub mod degrees;
pub mod demo;
pub mod draw;
pub mod flash;
pub mod font;
pub mod ili9325;
pub mod ili9341;
pub mod layout;
pub mod model;
pub mod scan;
pub mod screen;
pub mod slice;
pub mod theme;
pub mod ws_view;

pub use calibration::{CalFailure, CalPhase, CalibrationEvent, CalibrationFlow};
pub use draw::{Canvas, Run};
pub use layout::Layout;
pub use model::{warn, Page, Preview, Refusal, UiModel, UiState};
pub use screen::{hides, warning_line, Drawn, Hit, Redrawn, Ui, UiConfig};
pub use slice::{DrawBudget, PixelBudget, Unlimited};
