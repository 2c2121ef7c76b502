//! Effects: one room each, applied by the shade stage to a shaded pixel. A scene that does
//! not use an effect pays nothing for it: the shade loops are specialised per render on
//! which effects are present (see docs/ARCHITECTURE.md, "How to add an effect").
//!
//! - [`fog`]: depth cueing toward a fog colour with the distance from the eye.

pub(crate) mod fog;

pub(crate) use fog::FogEffect;
pub use fog::{Fog, FogMode};
