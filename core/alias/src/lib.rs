//! The core, `tessera-core`, under the workspace's name for it, `tessera`: every
//! item re-exported as it is. A firmware depends on `tessera-core` itself.
#![no_std]

pub use tessera_core::*;
