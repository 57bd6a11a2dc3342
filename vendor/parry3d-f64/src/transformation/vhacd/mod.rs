pub use self::parameters::VHACDParameters;
pub use self::vhacd::VHACD;

pub(crate) use self::vhacd::CutPlane;

mod parameters;
mod vhacd;
