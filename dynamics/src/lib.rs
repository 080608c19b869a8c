//! Train–bridge interaction dynamics (Xia, Xu & Chan 2000).
pub mod bridge;
pub mod error;

pub use error::InputError;
